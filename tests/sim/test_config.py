"""Config validation: every invalid value is rejected with one line naming field, value and rule."""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any, cast

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from workcell.errors import ConfigError, WorkcellError
from workcell.sim.config import (
    BoxConfig,
    ConveyorConfig,
    FeederConfig,
    RobotConfig,
    TargetConfig,
    WorldConfig,
)
from workcell.sim.scene import build_world_model

NAN = math.nan
INF = math.inf

# (id, construction, field named by the one problem line, value as printed)
SINGLE_PROBLEMS: list[tuple[str, Callable[[], object], str, str]] = [
    ("speed_zero", lambda: ConveyorConfig(speed=0.0), "conveyor.speed", "0"),
    ("speed_negative", lambda: ConveyorConfig(speed=-0.2), "conveyor.speed", "-0.2"),
    ("speed_nan", lambda: ConveyorConfig(speed=NAN), "conveyor.speed", "nan"),
    ("speed_inf", lambda: ConveyorConfig(speed=INF), "conveyor.speed", "inf"),
    ("length_nan", lambda: ConveyorConfig(length=NAN), "conveyor.length", "nan"),
    (
        "interval_zero",
        lambda: FeederConfig(release_interval_s=0.0),
        "feeder.release_interval_s",
        "0",
    ),
    (
        "interval_negative",
        lambda: FeederConfig(release_interval_s=-3.0),
        "feeder.release_interval_s",
        "-3",
    ),
    (
        "interval_nan",
        lambda: FeederConfig(release_interval_s=NAN),
        "feeder.release_interval_s",
        "nan",
    ),
    (
        "first_release_nan",
        lambda: FeederConfig(first_release_s=NAN),
        "feeder.first_release_s",
        "nan",
    ),
    ("pool_zero", lambda: FeederConfig(pool_size=0), "feeder.pool_size", "0"),
    ("mass_zero", lambda: BoxConfig(mass=0.0), "box.mass", "0"),
    ("mass_negative", lambda: BoxConfig(mass=-2.0), "box.mass", "-2"),
    ("mass_excessive", lambda: BoxConfig(mass=50.0), "box.mass", "50"),
    ("mass_nan", lambda: BoxConfig(mass=NAN), "box.mass", "nan"),
    ("mass_inf", lambda: BoxConfig(mass=INF), "box.mass", "inf"),
    ("size_nan", lambda: BoxConfig(size=(NAN, 0.3, 0.3)), "box.size", "(nan, 0.3, 0.3)"),
    ("rgba_nan", lambda: BoxConfig(rgba=(NAN, 0.5, 0.5, 1.0)), "box.rgba", "(nan, 0.5, 0.5, 1)"),
    ("target_center_nan", lambda: TargetConfig(center=(NAN, 0.0)), "target.center", "(nan, 0)"),
    ("target_height_nan", lambda: TargetConfig(table_height=NAN), "target.table_height", "nan"),
    ("target_zone_nan", lambda: TargetConfig(zone=(NAN, 0.7)), "target.zone", "(nan, 0.7)"),
    ("span_nan", lambda: RobotConfig(max_grasp_span=NAN), "robot.max_grasp_span", "nan"),
    ("start_pose_nan", lambda: RobotConfig(start_pose=(NAN, 0.0, 0.0)), "robot.start_pose", "nan"),
    ("timestep_nan", lambda: WorldConfig(timestep=NAN), "world.timestep", "nan"),
    (
        "target_on_conveyor",
        lambda: WorldConfig(target=TargetConfig(center=(-1.0, 0.0))),
        "world.target.center",
        "(-1, 0)",
    ),
    (
        "grasp_unknown",
        lambda: WorldConfig(grasp=cast(Any, "magnetic")),
        "world.grasp",
        "'magnetic'",
    ),
    (
        "box_wider_than_span",
        lambda: WorldConfig(
            conveyor=ConveyorConfig(width=0.8), box=BoxConfig(size=(0.3, 0.6, 0.3))
        ),
        "world.box.size",
        "(0.3, 0.6, 0.3)",
    ),
    (
        "span_narrower_than_box",
        lambda: WorldConfig(robot=RobotConfig(max_grasp_span=0.25)),
        "world.box.size",
        "(0.3, 0.3, 0.3)",
    ),
]


@pytest.mark.parametrize(
    ("make", "field", "value"),
    [pytest.param(make, field, value, id=name) for name, make, field, value in SINGLE_PROBLEMS],
)
def test_invalid_value_gives_one_problem_line(
    make: Callable[[], object], field: str, value: str
) -> None:
    with pytest.raises(ConfigError) as caught:
        make()
    problems = caught.value.problems
    assert len(problems) == 1, problems
    line = problems[0]
    assert "\n" not in line
    assert line.startswith(f"{field} = "), line
    assert value in line, line
    assert "must" in line, line  # says what is allowed
    assert isinstance(caught.value, WorkcellError)
    assert str(caught.value) == line


def test_box_wider_than_grasp_span_names_the_span() -> None:
    """With the default belt the 0.6 m box breaks two rules; one of them is the grasp span."""
    with pytest.raises(ConfigError) as caught:
        WorldConfig(box=BoxConfig(size=(0.3, 0.6, 0.3)))
    problems = caught.value.problems
    span_lines = [p for p in problems if "robot.max_grasp_span" in p]
    assert len(span_lines) == 1, problems
    assert span_lines[0].startswith("world.box.size = (0.3, 0.6, 0.3)")
    assert "0.55" in span_lines[0]
    assert all(p.startswith("world.box.size = ") for p in problems)


def test_several_problems_give_several_lines() -> None:
    with pytest.raises(ConfigError) as caught:
        ConveyorConfig(speed=0.0, length=-1.0, height=NAN)
    fields = [p.split(" = ")[0] for p in caught.value.problems]
    assert fields == ["conveyor.speed", "conveyor.length", "conveyor.height"]
    assert str(caught.value).count("\n") == 2


def test_several_world_level_problems_give_several_lines() -> None:
    with pytest.raises(ConfigError) as caught:
        WorldConfig(
            grasp=cast(Any, "magnetic"),
            timestep=0.0001,
            target=TargetConfig(center=(-1.0, 0.0)),
        )
    fields = sorted(p.split(" = ")[0] for p in caught.value.problems)
    assert fields == ["world.grasp", "world.target.center", "world.timestep"]


def test_defaults_construct_and_compile() -> None:
    config = WorldConfig()
    for part in (ConveyorConfig(), FeederConfig(), BoxConfig(), TargetConfig(), RobotConfig()):
        assert part is not None
    assert config.grasp == "assisted"
    model = build_world_model(config)
    assert model.nbody > 0


def test_physical_grasp_mode_is_valid() -> None:
    assert WorldConfig(grasp="physical").grasp == "physical"


@settings(max_examples=50, deadline=None)
@given(speed=st.floats(min_value=0.01, max_value=1.0))
def test_any_speed_in_range_is_accepted(speed: float) -> None:
    assert ConveyorConfig(speed=speed).speed == speed


@settings(max_examples=50, deadline=None)
@given(speed=st.floats(max_value=0.0, allow_nan=False) | st.just(NAN))
def test_any_non_positive_speed_is_rejected(speed: float) -> None:
    with pytest.raises(ConfigError) as caught:
        ConveyorConfig(speed=speed)
    assert len(caught.value.problems) == 1


@settings(max_examples=50, deadline=None)
@given(mass=st.floats(max_value=0.0) | st.floats(min_value=10.0, exclude_min=True))
def test_any_bad_mass_is_rejected(mass: float) -> None:
    with pytest.raises(ConfigError) as caught:
        BoxConfig(mass=mass)
    assert len(caught.value.problems) == 1
    assert caught.value.problems[0].startswith("box.mass = ")


@settings(max_examples=50, deadline=None)
@given(interval=st.floats(max_value=0.0, allow_nan=False))
def test_any_non_positive_interval_is_rejected(interval: float) -> None:
    with pytest.raises(ConfigError) as caught:
        FeederConfig(release_interval_s=interval)
    assert caught.value.problems[0].startswith("feeder.release_interval_s = ")

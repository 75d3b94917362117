"""The validation generated from the declarations: one line naming the setting, the value
and what is allowed, in the words of the template and the README."""

from __future__ import annotations

import math
from typing import Any, cast

import pytest

from workcell.audit.rows import recorded_rate
from workcell.errors import ConfigError
from workcell.session.config import RecordingConfig, SessionConfig, TaskConfig
from workcell.settings import check_as, declared_default
from workcell.sim.config import BoxConfig, FeederConfig, RobotConfig, TargetConfig


def problems(make: Any) -> list[str]:
    with pytest.raises(ConfigError) as caught:
        make()
    return list(caught.value.problems)


@pytest.mark.parametrize(
    ("make", "line"),
    [
        (
            lambda: TaskConfig(time_limit_s=0.0),
            "task.time_limit_s = 0: must be > 0 and at most 3600 s",
        ),
        (
            lambda: TaskConfig(rounds=cast(int, 2.0)),
            "task.rounds = 2: must be a whole number from 1 to 100 rounds",
        ),
        (
            lambda: TaskConfig(level_boxes=(1, 21, 3)),
            "task.level_boxes[1] = 21: must be a whole number from 1 to 20 boxes",
        ),
        (
            lambda: TaskConfig(level_boxes=()),
            "task.level_boxes = (): must list at least 1 item",
        ),
        (
            lambda: RecordingConfig(sampling_rate_hz=math.inf),
            "recording.sampling_rate_hz = inf: must be a finite number > 0 Hz",
        ),
        (
            lambda: FeederConfig(pool_size=13),
            "feeder.pool_size = 13: must be a whole number from 1 to 12 boxes",
        ),
        (
            lambda: BoxConfig(size=cast(Any, (0.3, 0.3))),
            "box.size = (0.3, 0.3): must have exactly 3 components",
        ),
        (
            lambda: BoxConfig(size=(0.3, 0.7, 0.3)),
            "box.size = (0.3, 0.7, 0.3): every component must be between 0.05 and 0.6 m",
        ),
        (
            lambda: TargetConfig(center=(9.0, 0.0)),
            "target.center = (9, 0): every component must be between -5 and 5 m",
        ),
        (
            lambda: RobotConfig(start_pose=(0.0, math.inf, 0.0)),
            "robot.start_pose = (0, inf, 0): every component must be between -5 and 5 m, m, rad",
        ),
        (  # inside the walls: far beyond them the physics fails silently on the first step
            lambda: RobotConfig(start_pose=(1e308, 0.0, 0.0)),
            "robot.start_pose = (1e+308, 0, 0): every component must be between -5 and 5 m, m, rad",
        ),
        (
            lambda: SessionConfig(seed=-1),
            "seed = -1: must be a whole number from 0 to 2^63-1",
        ),
        (
            lambda: SessionConfig(operator_id="x" * 65),
            f"operator_id = '{'x' * 65}': must be 1 to 64 letters, digits, '.', '_' or '-'",
        ),
    ],
)
def test_a_bad_value_is_one_line_with_what_is_allowed(make: Any, line: str) -> None:
    assert problems(make) == [line]


def test_bounds_are_inclusive_unless_declared_open() -> None:
    assert TaskConfig(time_limit_s=3600.0).time_limit_s == 3600.0
    assert TaskConfig(countdown_s=0.0).countdown_s == 0.0
    assert RecordingConfig(grip_threshold=1.0).grip_threshold == 1.0
    assert problems(lambda: RecordingConfig(grip_threshold=0.0)) == [
        "recording.grip_threshold = 0: must be > 0 and at most 1"
    ]


def test_the_audit_takes_the_rate_from_the_recording_declaration() -> None:
    default = RecordingConfig().sampling_rate_hz
    assert recorded_rate({"recording": {"sampling_rate_hz": 40}}) == (40.0, None)
    rate, note = recorded_rate({"rate_hz": 40})
    assert rate == default
    assert note == f"parameters hold no recording.sampling_rate_hz; {default:g} Hz was assumed"
    rate, note = recorded_rate({"recording": {"sampling_rate_hz": -5}})
    assert rate == default
    assert note == (
        f"recording.sampling_rate_hz = -5: must be a finite number > 0 Hz; "
        f"{default:g} Hz was assumed"
    )


def test_a_flag_that_sets_a_setting_is_checked_by_its_declaration() -> None:
    assert declared_default(TaskConfig, "time_limit_s") == TaskConfig().time_limit_s
    assert check_as(TaskConfig, "time_limit_s", "--time-limit", 30.0) == []
    assert check_as(TaskConfig, "time_limit_s", "--time-limit", 0.0) == [
        "--time-limit = 0: must be > 0 and at most 3600 s"
    ]
    assert check_as(TaskConfig, "time_limit_s", "--time-limit", math.inf) == [
        "--time-limit = inf: must be > 0 and at most 3600 s"
    ]
    with pytest.raises(TypeError, match="not declared"):
        check_as(TaskConfig, "levels", "--levels", 1)
    with pytest.raises(TypeError, match="not declared"):
        declared_default(TaskConfig, "nothing")

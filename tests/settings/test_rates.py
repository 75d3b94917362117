"""The one divisibility rule for rates and steps, and its one-line error everywhere."""

from __future__ import annotations

import pytest

from workcell.envs.config import BoxTransferConfig
from workcell.errors import ConfigError
from workcell.session.config import RecordingConfig, SessionConfig
from workcell.settings.rates import divides, steps_per
from workcell.sim.config import RobotConfig, WorldConfig


@pytest.mark.parametrize(
    ("fast", "slow", "steps"),
    [
        (400.0, 20.0, 20),
        (400.0, 400.0, 1),
        (1 / 0.0025, 40.0, 10),  # a timestep that is not exact in binary
        (1 / 0.0003, 1 / 0.0009, 3),
        (400.0, 30.0, None),
        (400.0, 800.0, None),
        (400.0, 0.0, None),
        (400.0, float("nan"), None),
        (40.0, 2.5, 16),
    ],
)
def test_steps_per(fast: float, slow: float, steps: int | None) -> None:
    assert steps_per(fast, slow) == steps


def test_the_error_names_the_setting_the_value_the_rate_and_what_divides_it() -> None:
    (line,) = divides("recording.sampling_rate_hz", 30.0, 400.0, "the physics rate")
    assert line == (
        "recording.sampling_rate_hz = 30: must divide the physics rate = 400 Hz into a whole "
        "number of steps, e.g. 20, 25, 40 or 50"
    )
    (whole,) = divides("r", 2.5, 40.0, "the control rate", whole=True)
    assert whole == (
        "r = 2.5: must be a whole number of Hz that divides the control rate = 40 Hz into a "
        "whole number of steps, e.g. 1, 2, 4 or 5"
    )
    assert divides("r", 20.0, 400.0, "x") == []
    assert divides("r", 8.0, 40.0, "x", whole=True) == []


def test_the_session_the_world_and_the_environment_use_the_one_rule() -> None:
    with pytest.raises(ConfigError) as session:
        SessionConfig(recording=RecordingConfig(sampling_rate_hz=30.0))
    assert list(session.value.problems) == [
        "recording.sampling_rate_hz = 30: must divide the physics rate 1/world.timestep = "
        "400 Hz into a whole number of steps, e.g. 20, 25, 40 or 50"
    ]
    with pytest.raises(ConfigError) as world:
        WorldConfig(robot=RobotConfig(control_hz=30.0))
    assert list(world.value.problems) == [
        "world.robot.control_hz = 30: must divide the physics rate 1/world.timestep = 400 Hz "
        "into a whole number of steps, e.g. 20, 25, 40 or 50"
    ]
    with pytest.raises(ConfigError) as env:
        BoxTransferConfig(session=SessionConfig(recording=RecordingConfig(sampling_rate_hz=50.0)))
    assert list(env.value.problems) == [
        "recording.sampling_rate_hz = 50: must be a whole number of Hz that divides the "
        "control rate world.robot.control_hz = 40 Hz into a whole number of steps, "
        "e.g. 8, 10, 20 or 40"
    ]


def test_step_counts_come_from_the_rule() -> None:
    config = SessionConfig(
        recording=RecordingConfig(sampling_rate_hz=10.0),
        world=WorldConfig(timestep=0.002, robot=RobotConfig(control_hz=50.0)),
    )
    assert config.physics_steps_per_frame == 50
    assert config.world.control_substeps == 10
    assert BoxTransferConfig(session=config).control_steps_per_frame == 5

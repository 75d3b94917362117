"""How raw device state is turned into commands: dead zones, speeds, limits."""

from __future__ import annotations

import math
from dataclasses import dataclass

from workcell.errors import ConfigError
from workcell.session.config import InputConfig, RecordingConfig, SessionConfig
from workcell.settings import declared_problems, same_as, section, setting
from workcell.sim.config import RobotConfig


@dataclass(frozen=True)
class TeleopConfig:
    """Mapping parameters; :meth:`for_session` takes speeds and the grip threshold from a
    session's settings so a human drives within the same limits as the expert (their
    defaults and allowed values are those settings' declarations)."""

    max_linear_speed: float = same_as(
        RobotConfig, "max_linear_speed", "full stick deflection (the robot's max_linear_speed)"
    )
    max_yaw_rate: float = same_as(
        RobotConfig, "max_yaw_rate", "full right-stick deflection (the robot's max_yaw_rate)"
    )
    yaw_accel: float = same_as(
        RobotConfig, "yaw_accel", "how fast a snap turn can brake (the robot's yaw_accel)"
    )
    dead_zone: float = setting(
        0.15,
        "stick deflection below this counts as zero; above it the scale starts at zero",
        unit="1",
        low=0.0,
        high=0.9,
    )
    grip_threshold: float = same_as(RecordingConfig, "grip_threshold")
    motion_scale: float = setting(
        1.0,
        "metres of TCP motion per metre of controller motion",
        unit="1",
        low=0.0,
        low_open=True,
        high=10.0,
    )
    head_pan_limits: tuple[float, float] = setting(
        (-1.6, 1.6), "lowest and highest head pan", unit="rad", low=-math.pi, high=math.pi, length=2
    )
    head_tilt_limits: tuple[float, float] = setting(
        (-0.8, 1.2),
        "lowest and highest head tilt",
        unit="rad",
        low=-math.pi,
        high=math.pi,
        length=2,
    )
    default_head: tuple[float, float] = setting(
        (0.0, 0.3),
        "head pan and tilt when no headset is tracked",
        unit="rad",
        low=-math.pi,
        high=math.pi,
        length=2,
    )
    input_timeout_s: float = setting(
        0.5,
        "older input than this stops the base (a dropped or stalled link)",
        unit="s",
        low=0.0,
        low_open=True,
        high=10.0,
    )
    clutch_hold_s: float = setting(
        3.0,
        "a grip held when the input stalls stays engaged for this long: the arm waits at "
        "its target, then follows the hand on from the same anchor, so no hand motion is "
        "lost; a longer gap lets go (the grip must be pressed again)",
        unit="s",
        low=0.0,
        high=60.0,
    )

    input: InputConfig = section(
        lambda: InputConfig(filter="off"),
        "pose filtering (off unless the session's input settings ask for it, as they do by "
        "default)",
    )

    def __post_init__(self) -> None:
        problems = declared_problems(self, "teleop")
        if problems:
            raise ConfigError(problems)

    @classmethod
    def for_session(cls, config: SessionConfig) -> TeleopConfig:
        robot = config.world.robot
        return cls(
            max_linear_speed=robot.max_linear_speed,
            max_yaw_rate=robot.max_yaw_rate,
            yaw_accel=robot.yaw_accel,
            grip_threshold=config.recording.grip_threshold,
            input=config.input,
        )

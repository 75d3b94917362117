"""How raw device state is turned into commands: dead zones, speeds, limits."""

from __future__ import annotations

from dataclasses import dataclass

from workcell.session.config import SessionConfig


@dataclass(frozen=True)
class TeleopConfig:
    """Mapping parameters; :meth:`for_session` takes speeds and the grip threshold from a
    session's settings so a human drives within the same limits as the expert."""

    max_linear_speed: float = 0.8
    """Full stick deflection, m/s (the robot's ``max_linear_speed``)."""
    max_yaw_rate: float = 1.2
    """Full right-stick deflection, rad/s (the robot's ``max_yaw_rate``)."""
    dead_zone: float = 0.15
    """Stick deflection below this counts as zero; above it the scale starts at zero."""
    grip_threshold: float = 0.5
    """A grip value at or above this engages arm following."""
    motion_scale: float = 1.0
    """Metres of TCP motion per metre of controller motion."""
    head_pan_limits: tuple[float, float] = (-1.6, 1.6)
    head_tilt_limits: tuple[float, float] = (-0.8, 1.2)
    default_head: tuple[float, float] = (0.0, 0.3)
    """Head pan and tilt (rad) when no headset is tracked."""
    input_timeout_s: float = 0.5
    """Older input than this stops the base (a dropped or stalled link)."""

    @classmethod
    def for_session(cls, config: SessionConfig) -> TeleopConfig:
        robot = config.world.robot
        return cls(
            max_linear_speed=robot.max_linear_speed,
            max_yaw_rate=robot.max_yaw_rate,
            grip_threshold=config.recording.grip_threshold,
        )

"""Sticks → base twist and headset → head pan/tilt: stateless mappings."""

from __future__ import annotations

import math

from workcell.control.command import BaseTwist
from workcell.teleop.config import TeleopConfig
from workcell.teleop.rotation import Quat, rotate, xr_to_base_rotation


def dead_zone(x: float, y: float, zone: float) -> tuple[float, float]:
    """Radial dead zone: inside ``zone`` nothing, outside rescaled so the edge of the zone
    is 0 and full deflection stays 1 (the direction is kept)."""
    magnitude = math.hypot(x, y)
    if magnitude <= zone:
        return 0.0, 0.0
    scale = min(1.0, (magnitude - zone) / (1.0 - zone)) / magnitude
    return x * scale, y * scale


def base_twist(
    left: tuple[float, float], right: tuple[float, float], config: TeleopConfig
) -> BaseTwist:
    """Left stick: forward (y up) and strafe (x right → move right, i.e. -y in the base);
    right stick x: turn (right → clockwise, i.e. negative yaw rate)."""
    strafe, forward = dead_zone(left[0], left[1], config.dead_zone)
    turn, _ = dead_zone(right[0], 0.0, config.dead_zone)
    return BaseTwist(
        vx=forward * config.max_linear_speed,
        vy=-strafe * config.max_linear_speed,
        wz=-turn * config.max_yaw_rate,
    )


def head_angles(headset_quat: Quat | None, config: TeleopConfig) -> tuple[float, float]:
    """Pan (left positive) and tilt (down positive) that look where the headset looks,
    clamped to the head's range."""
    if headset_quat is None:
        return config.default_head
    fx, fy, fz = rotate(xr_to_base_rotation(headset_quat), (1.0, 0.0, 0.0))
    pan = math.atan2(fy, fx)
    tilt = math.atan2(-fz, math.hypot(fx, fy))
    low_pan, high_pan = config.head_pan_limits
    low_tilt, high_tilt = config.head_tilt_limits
    return min(max(pan, low_pan), high_pan), min(max(tilt, low_tilt), high_tilt)

"""Sticks → base twist, headset → head; numbers worked out by hand."""

from __future__ import annotations

import math

import pytest

from workcell.teleop.config import TeleopConfig
from workcell.teleop.mapping import base_twist, dead_zone, head_angles

CONFIG = TeleopConfig(max_linear_speed=0.8, max_yaw_rate=1.2, dead_zone=0.2)


def test_dead_zone() -> None:
    assert dead_zone(0.1, 0.1, 0.2) == (0.0, 0.0)
    assert dead_zone(0.0, 1.0, 0.2) == (0.0, 1.0)
    assert dead_zone(0.0, 0.6, 0.2) == pytest.approx((0.0, 0.5))  # (0.6 - 0.2) / (1 - 0.2)
    assert dead_zone(-0.6, 0.0, 0.2) == pytest.approx((-0.5, 0.0))


def test_left_stick_forward_and_strafe_right_stick_turns() -> None:
    forward = base_twist((0.0, 1.0), (0.0, 0.0), CONFIG)
    assert (forward.vx, forward.vy, forward.wz) == pytest.approx((0.8, 0.0, 0.0))
    right = base_twist((1.0, 0.0), (0.0, 0.0), CONFIG)  # stick right: move right = -y
    assert (right.vx, right.vy) == pytest.approx((0.0, -0.8))
    turn = base_twist((0.0, 0.0), (1.0, 0.0), CONFIG)  # stick right: turn clockwise
    assert turn.wz == pytest.approx(-1.2)
    idle = base_twist((0.05, -0.1), (0.1, 0.9), CONFIG)  # right stick y does nothing
    assert (idle.vx, idle.vy, idle.wz) == (0.0, 0.0, 0.0)


def _about(axis: tuple[float, float, float], angle: float) -> tuple[float, float, float, float]:
    s = math.sin(angle / 2)
    return (math.cos(angle / 2), axis[0] * s, axis[1] * s, axis[2] * s)


def test_head_follows_the_headset() -> None:
    assert head_angles(None, CONFIG) == CONFIG.default_head
    assert head_angles((1.0, 0.0, 0.0, 0.0), CONFIG) == pytest.approx((0.0, 0.0))
    look_left = _about((0.0, 1.0, 0.0), 0.5)  # yaw + about XR up
    assert head_angles(look_left, CONFIG) == pytest.approx((0.5, 0.0))
    look_down = _about((1.0, 0.0, 0.0), -0.4)  # pitch - about XR right
    assert head_angles(look_down, CONFIG) == pytest.approx((0.0, 0.4))


def test_head_is_clamped() -> None:
    pan, _ = head_angles(_about((0.0, 1.0, 0.0), 2.5), CONFIG)
    assert pan == CONFIG.head_pan_limits[1]
    _, tilt = head_angles(_about((1.0, 0.0, 0.0), 1.3), CONFIG)  # look far up
    assert tilt == CONFIG.head_tilt_limits[0]

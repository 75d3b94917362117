"""The clutch mapping: controller motion since engage moves the TCP target, in base axes."""

from __future__ import annotations

import math

import pytest

from workcell.teleop.clutch import ArmClutch, Pose

TARGET: Pose = (0.5, 0.2, 1.0, 1.0, 0.0, 0.0, 0.0)
START: Pose = (0.1, 1.2, -0.3, 1.0, 0.0, 0.0, 0.0)


def at(x: float, y: float, z: float, quat: tuple[float, ...] = (1.0, 0.0, 0.0, 0.0)) -> Pose:
    return (x, y, z, quat[0], quat[1], quat[2], quat[3])


def target_of(clutch: ArmClutch, held: bool, controller: Pose | None) -> Pose:
    command = clutch.update(held, controller, lambda: TARGET)
    return (*command.position, *command.quaternion)


def test_ten_centimetres_forward_in_xr_is_plus_x_in_the_base() -> None:
    clutch = ArmClutch()
    assert target_of(clutch, True, START) == pytest.approx(TARGET)
    moved = target_of(clutch, True, at(0.1, 1.2, -0.4))  # -z in XR = forward
    assert moved == pytest.approx((0.6, 0.2, 1.0, 1.0, 0.0, 0.0, 0.0))


def test_left_and_up() -> None:
    clutch = ArmClutch()
    target_of(clutch, True, START)
    moved = target_of(clutch, True, at(0.0, 1.25, -0.3))  # 10 cm left (-x), 5 cm up (+y)
    assert moved[:3] == pytest.approx((0.5, 0.3, 1.05))


def test_motion_scale() -> None:
    clutch = ArmClutch(motion_scale=0.5)
    target_of(clutch, True, START)
    assert target_of(clutch, True, at(0.1, 1.2, -0.5))[:3] == pytest.approx((0.6, 0.2, 1.0))


def test_rotation_since_engage_turns_the_target_about_base_axes() -> None:
    clutch = ArmClutch()
    held = (math.cos(0.3), 0.0, math.sin(0.3), 0.0)  # the controller is already turned
    target_of(clutch, True, at(0.1, 1.2, -0.3, held))
    # a further 0.6 rad about XR up (+y): the target turns 0.6 rad about base up (+z)
    more = (math.cos(0.3), 0.0, math.sin(0.3), 0.0)
    w = held[0] * more[0] - held[2] * more[2]
    y = held[0] * more[2] + held[2] * more[0]
    turned = target_of(clutch, True, at(0.1, 1.2, -0.3, (w, 0.0, y, 0.0)))
    assert turned[3:] == pytest.approx((math.cos(0.3), 0.0, 0.0, math.sin(0.3)))
    assert turned[:3] == pytest.approx(TARGET[:3])


def test_release_freezes_and_reengaging_does_not_jump() -> None:
    clutch = ArmClutch()
    target_of(clutch, True, START)
    target_of(clutch, True, at(0.1, 1.2, -0.4))  # target now x = 0.6
    released = clutch.update(False, at(0.1, 1.2, -0.9), lambda: TARGET)
    assert not released.follow and released.position == pytest.approx((0.6, 0.2, 1.0))
    # the hand moved 0.5 m while released; re-engaging there anchors afresh at the arm's
    # current target (x = 0.6), so nothing jumps
    frozen: Pose = (0.6, 0.2, 1.0, 1.0, 0.0, 0.0, 0.0)
    again = clutch.update(True, at(0.1, 1.2, -0.9), lambda: frozen)
    assert again.follow and again.position == pytest.approx((0.6, 0.2, 1.0))
    after = clutch.update(True, at(0.1, 1.2, -1.0), lambda: TARGET)  # not read again
    assert after.position == pytest.approx((0.7, 0.2, 1.0))


def test_current_target_is_read_only_at_engage() -> None:
    clutch = ArmClutch()
    calls: list[int] = []

    def current() -> Pose:
        calls.append(1)
        return TARGET

    for z in (-0.3, -0.35, -0.4):
        clutch.update(True, at(0.1, 1.2, z), current)
    assert len(calls) == 1


def test_lost_tracking_freezes_then_anchors_afresh() -> None:
    clutch = ArmClutch()
    target_of(clutch, True, START)
    target_of(clutch, True, at(0.1, 1.2, -0.4))
    lost = clutch.update(True, None, lambda: TARGET)
    assert not lost.follow and lost.position == pytest.approx((0.6, 0.2, 1.0))
    frozen: Pose = (0.6, 0.2, 1.0, 1.0, 0.0, 0.0, 0.0)
    back = clutch.update(True, at(5.0, 1.0, 3.0), lambda: frozen)
    assert back.position == pytest.approx((0.6, 0.2, 1.0))


def test_never_engaged_is_not_following() -> None:
    command = ArmClutch().update(False, START, lambda: TARGET)
    assert not command.follow

"""TeleopOperator: the newest input becomes the command; the recorder sees the raw input."""

from __future__ import annotations

from typing import Any, cast

import pytest

from workcell.protocol.messages import ControllerState, Input
from workcell.sim.world import World
from workcell.teleop.clutch import Pose
from workcell.teleop.config import TeleopConfig
from workcell.teleop.operator import TeleopOperator

CURRENT: Pose = (0.4, 0.25, 0.9, 1.0, 0.0, 0.0, 0.0)
WORLD = cast(World, object())  # the operator only passes the world to its TCP source


class Clock:
    def __init__(self) -> None:
        self.now = 100.0

    def __call__(self) -> float:
        return self.now


def hand(**changes: Any) -> ControllerState:
    values: dict[str, Any] = {
        "pose": (0.2, 1.1, -0.3, 1.0, 0.0, 0.0, 0.0),
        "grip": 0.0,
        "trigger": 0.0,
        "stick": (0.0, 0.0),
        "buttons": 0,
    }
    return ControllerState(**{**values, **changes})


def message(seq: int, left: ControllerState | None = None, **kw: Any) -> Input:
    return Input(
        seq=seq,
        t_client=0.0,
        source="xr",
        headset=kw.get("headset"),
        left=left or hand(),
        right=kw.get("right") or hand(),
    )


@pytest.fixture
def clock() -> Clock:
    return Clock()


@pytest.fixture
def operator(clock: Clock) -> TeleopOperator:
    return TeleopOperator(TeleopConfig(), tcp_source=lambda world, side: CURRENT, clock=clock)


def test_no_input_yet_is_a_still_robot(operator: TeleopOperator) -> None:
    command = operator.act(WORLD)
    assert (command.base.vx, command.base.vy, command.base.wz) == (0.0, 0.0, 0.0)
    assert not command.left.follow and not command.right.follow
    assert operator.operator_input() is None
    assert operator.applied_seq == -1


def test_sticks_grip_and_trigger(operator: TeleopOperator) -> None:
    left = hand(stick=(0.0, 1.0), grip=0.9, trigger=0.7)
    assert operator.submit(message(1, left))
    command = operator.act(WORLD)
    assert command.base.vx == pytest.approx(0.8)
    assert command.left.follow and command.left.position == pytest.approx(CURRENT[:3])
    assert not command.right.follow
    assert command.close_left == pytest.approx(0.7) and command.close_right == 0.0
    assert operator.applied_seq == 1
    moved = hand(pose=(0.2, 1.1, -0.4, 1.0, 0.0, 0.0, 0.0), grip=0.9, trigger=0.7)
    operator.submit(message(2, moved))
    assert operator.act(WORLD).left.position == pytest.approx((0.5, 0.25, 0.9))


def test_grip_threshold_comes_from_the_session() -> None:
    from workcell.session.config import RecordingConfig, SessionConfig

    config = TeleopConfig.for_session(SessionConfig(recording=RecordingConfig(grip_threshold=0.8)))
    operator = TeleopOperator(config, tcp_source=lambda world, side: CURRENT)
    operator.submit(message(1, hand(grip=0.7)))
    assert not operator.act(WORLD).left.follow
    operator.submit(message(2, hand(grip=0.8)))
    assert operator.act(WORLD).left.follow


def test_old_sequence_numbers_are_dropped(operator: TeleopOperator) -> None:
    assert operator.submit(message(5))
    assert not operator.submit(message(5))
    assert not operator.submit(message(3))
    operator.new_link()
    assert operator.submit(message(1))  # a reconnected client counts afresh


def test_stale_input_stops_the_base_and_freezes_the_arms(
    operator: TeleopOperator, clock: Clock
) -> None:
    operator.submit(message(1, hand(stick=(0.0, 1.0), grip=1.0, trigger=1.0)))
    assert operator.act(WORLD).base.vx > 0
    clock.now += 0.6  # beyond input_timeout_s = 0.5
    command = operator.act(WORLD)
    assert command.base.vx == 0.0
    assert command.left.position == pytest.approx(CURRENT[:3])  # the arm waits
    assert command.left.follow and operator.clutches["l"].engaged  # the grip is not lost
    assert command.close_left == 1.0  # a held box is not dropped
    assert not command.right.follow and not operator.clutches["r"].engaged  # never gripped


MOVED = (0.35, 1.05, -0.42, 1.0, 0.0, 0.0, 0.0)
"""Where the hand is when input returns: 15 cm right, 5 cm down, 12 cm forward."""


def _target_after_gap(gap_s: float, grip_back: float = 1.0) -> tuple[float, ...]:
    """The left arm's target once input returns after ``gap_s`` without input, the hand
    having moved from its first pose to MOVED meanwhile."""
    clock = Clock()
    operator = TeleopOperator(TeleopConfig(), tcp_source=lambda world, side: CURRENT, clock=clock)
    operator.submit(message(1, hand(grip=1.0)))
    operator.act(WORLD)
    steps = round(gap_s / 0.025)
    for _ in range(steps):  # the control loop runs on at 40 Hz through the gap
        clock.now += gap_s / steps
        operator.act(WORLD)
    operator.submit(message(2, hand(grip=grip_back, pose=MOVED)))
    command = operator.act(WORLD)
    return (*command.left.position, *command.left.quaternion, float(command.left.follow))


def test_a_short_input_gap_loses_neither_the_clutch_nor_the_hands_motion() -> None:
    without_gap = _target_after_gap(0.0)
    assert without_gap[:3] != pytest.approx(CURRENT[:3])  # the hand's motion moved the target
    assert _target_after_gap(0.6) == pytest.approx(without_gap)  # 0.6 s > input_timeout_s
    assert _target_after_gap(2.9) == pytest.approx(without_gap)  # within clutch_hold_s = 3


def test_a_long_gap_lets_go_and_the_arm_re_anchors_where_it_is() -> None:
    target = _target_after_gap(3.5)  # beyond clutch_hold_s: the grip must be taken again
    assert target[:3] == pytest.approx(CURRENT[:3]) and target[-1] == 1.0  # no jump


def test_a_grip_released_during_the_gap_lets_go() -> None:
    target = _target_after_gap(0.6, grip_back=0.0)
    assert target[:3] == pytest.approx(CURRENT[:3]) and target[-1] == 0.0


def test_operator_input_for_the_recorder(operator: TeleopOperator, clock: Clock) -> None:
    headset: Pose = (0.0, 1.6, 0.0, 1.0, 0.0, 0.0, 0.0)
    right = hand(grip=0.3, trigger=0.2, stick=(0.5, -0.5), buttons=3)
    operator.submit(message(1, hand(grip=0.6), right=right, headset=headset))
    clock.now += 0.04
    raw = operator.operator_input()
    assert raw is not None
    assert raw.grip == (0.6, 0.3) and raw.trigger == (0.0, 0.2)
    assert raw.controller_l == hand().pose and raw.headset == headset
    assert raw.stick_r == (0.5, -0.5) and raw.buttons == (0, 3)
    assert raw.age_s == pytest.approx(0.04)


def test_new_trial_forgets_arm_targets(operator: TeleopOperator) -> None:
    operator.submit(message(1, hand(grip=1.0)))
    operator.act(WORLD)
    operator.start_trial(7)
    assert all(not c.engaged and c.target is None for c in operator.clutches.values())

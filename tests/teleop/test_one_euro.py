"""The One-Euro pose filter: values against hand computation, jitter removed at rest, little
lag in motion, quaternion sign flips, and the teleop operator driving the arms with the
filtered poses while the recorder keeps the raw ones."""

from __future__ import annotations

import math
import statistics

import numpy as np
import pytest

from tests.teleop.test_operator import CURRENT, WORLD, Clock, hand, message
from workcell.session.config import InputConfig, SessionConfig
from workcell.teleop.clutch import Pose
from workcell.teleop.config import TeleopConfig
from workcell.teleop.one_euro import OneEuro, OneEuroParameters, PoseFilter
from workcell.teleop.operator import TeleopOperator

RATE_HZ = 72.0
"""A Quest's frame rate: one pose sample per frame."""


def test_two_samples_against_hand_computation() -> None:
    # dt = 0.1, x 0 -> 1: the speed estimate is a_d * 10 with a_d = 1 / (1 + 1 / (2 pi 0.1))
    a_d = 1.0 / (1.0 + 1.0 / (2.0 * math.pi * 0.1))
    for beta, cutoff in ((0.0, 1.5), (1.0, 1.5 + 10.0 * a_d)):
        one_euro = OneEuro(OneEuroParameters(1.5, beta, 1.0))
        assert one_euro(0.0, (0.0,)) == (0.0,)  # the first sample passes as it is
        a = 1.0 / (1.0 + 1.0 / (2.0 * math.pi * cutoff * 0.1))
        assert one_euro(0.1, (1.0,)) == pytest.approx((a,))
    assert one_euro(0.1, (5.0,)) == pytest.approx((a,))  # no time elapsed: ignored
    one_euro.reset()
    assert one_euro(0.2, (5.0,)) == (5.0,)


def defaults() -> PoseFilter:
    c = InputConfig()
    return PoseFilter(c.min_cutoff_hz, c.beta_position, c.beta_rotation, c.d_cutoff_hz)


def test_a_still_hand_loses_its_jitter() -> None:
    rng = np.random.default_rng(0)
    pose_filter = defaults()
    raw, filtered = [], []
    for k in range(int(4 * RATE_HZ)):
        noisy = 0.3 + rng.normal(0.0, 0.002)  # 2 mm of tracking noise
        raw.append(noisy)
        filtered.append(pose_filter(k / RATE_HZ, (noisy, 1.0, -0.3, 1.0, 0.0, 0.0, 0.0))[0])
    settled = int(RATE_HZ)
    ratio = statistics.pstdev(filtered[settled:]) / statistics.pstdev(raw[settled:])
    assert ratio < 0.35, f"the filter kept {ratio:.0%} of the jitter"


def test_a_fast_hand_lags_far_less_than_a_fixed_low_pass() -> None:
    def lag(beta: float) -> float:
        one_euro = OneEuro(OneEuroParameters(InputConfig().min_cutoff_hz, beta, 1.0))
        out: tuple[float, ...] = (0.0,)
        for k in range(int(RATE_HZ)):  # one second at 0.5 m/s
            out = one_euro(k / RATE_HZ, (0.5 * k / RATE_HZ,))
        return 0.5 * (int(RATE_HZ) - 1) / RATE_HZ - out[0]

    fixed, adaptive = lag(0.0), lag(InputConfig().beta_position)
    assert fixed > 0.04  # a 1.5 Hz low-pass trails 0.5 m/s by about 5 cm
    assert adaptive < fixed / 4, (adaptive, fixed)


def test_quaternion_sign_flips_do_not_disturb_the_rotation() -> None:
    pose_filter = defaults()
    half = math.pi / 8  # 45 degrees about z
    quat = (math.cos(half), 0.0, 0.0, math.sin(half))
    for k in range(50):
        sign = 1.0 if k % 2 else -1.0  # the same rotation, alternately as q and -q
        w, x, y, z = (sign * q for q in quat)
        out = pose_filter(k / RATE_HZ, (0.0, 0.0, 0.0, w, x, y, z))
        assert math.isclose(math.fsum(q * q for q in out[3:]), 1.0, rel_tol=1e-9)
        assert abs(sum(a * b for a, b in zip(out[3:], quat, strict=True))) == pytest.approx(1.0)


def test_the_arm_follows_the_filtered_pose_and_the_record_keeps_the_raw() -> None:
    rng = np.random.default_rng(1)

    def target_jitter(config: TeleopConfig) -> tuple[float, list[Pose]]:
        clock = Clock()
        operator = TeleopOperator(config, tcp_source=lambda world, side: CURRENT, clock=clock)
        targets, raws, recorded_z = [], [], []
        for seq in range(1, int(3 * RATE_HZ)):
            z = -0.3 + rng.normal(0.0, 0.002)
            pose = (0.2, 1.1, z, 1.0, 0.0, 0.0, 0.0)
            operator.submit(message(seq, hand(pose=pose, grip=1.0)))
            clock.now += 1.0 / RATE_HZ
            targets.append(operator.act(WORLD).left.position[0])
            recorded = operator.operator_input()
            assert recorded is not None and recorded.controller_l == pose  # raw, as it came
            assert recorded.filtered_l is not None  # and beside it what the arm followed
            recorded_z.append(recorded.filtered_l[2])
            raws.append(pose)
        settled = int(RATE_HZ)
        # the recorded filtered pose is the one the arm's target moved with
        assert statistics.pstdev(recorded_z[settled:]) == pytest.approx(
            statistics.pstdev(targets[settled:]), rel=0.05
        )
        return statistics.pstdev(targets[settled:]), raws

    filtered, _ = target_jitter(TeleopConfig.for_session(SessionConfig()))
    unfiltered, _ = target_jitter(
        TeleopConfig.for_session(SessionConfig(input=InputConfig(filter="off")))
    )
    assert filtered < 0.35 * unfiltered, (filtered, unfiltered)

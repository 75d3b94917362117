"""Path length, grip-gated smoothness and active-action ratio on hand-built frames.

Every expected value is worked out by hand in the comments, not with the metric's formula.
"""

from __future__ import annotations

import math

import pytest

from tests.metrics.builders import frames, positions
from workcell.metrics import MetricThresholds, compute_trial_metrics

DEFAULT = MetricThresholds()


def test_path_length_sums_midpoint_steps() -> None:
    left = [(0, 0, 0), (6, 0, 0), (6, 8, 0), (6, 8, 0), (6, 8, 4), (9, 8, 4), (10, 8, 4)]
    right = [(0, 2, 0), (0, 2, 0), (0, 2, 0), (0, 2, 0), (0, 2, 0), (0, 6, 0), (-1, 6, 0)]
    trial = frames(7, **positions("tcp_l", left), **positions("tcp_r", right))
    # midpoint steps = (left step + right step) / 2:
    #   (3, 0, 0) -> 3;  (0, 4, 0) -> 4;  still -> 0;  (0, 0, 2) -> 2;
    #   ((3 + 0) / 2, (0 + 4) / 2, 0) = (1.5, 2, 0) -> 2.5;
    #   arms move +1 and -1 in x: the midpoint stays -> 0.      total 11.5 m
    assert compute_trial_metrics(trial, False, DEFAULT).path_length_m == pytest.approx(11.5)


def test_path_length_of_one_and_zero_frames_is_zero() -> None:
    one = frames(1, **positions("tcp_l", [(1, 2, 3)]))
    assert compute_trial_metrics(one, False, DEFAULT).path_length_m == 0.0
    assert compute_trial_metrics(frames(0), False, DEFAULT).path_length_m == 0.0


def test_smoothness_pools_both_arms_over_their_own_grip_intervals() -> None:
    trial = frames(
        7,
        # left grip active at t = 1..4 (0.5 sits exactly on the threshold: active), so the
        # centres with t-1, t, t+1 all active are t = 2, 3
        grip_l=[0.0, 0.5, 0.7, 0.8, 0.9, 0.2, 0.0],
        # right grip active at t = 2..6: centres t = 3, 4, 5
        grip_r=[0.0, 0.0, 1.0, 1.0, 1.0, 1.0, 1.0],
        # |q[t+1] - 2 q[t] + q[t-1]|: t=2: |3 - 2 + 0| = 1, t=3: |6 - 6 + 1| = 1
        # (t=5 would give |50 - 20 + 6| = 36: excluded, the left grip is off at t=5)
        q_arm_l_1=[0, 0, 1, 3, 6, 10, 50],
        # t=2: |0 - 0 + 0| = 0, t=3: |2 - 0 + 0| = 2
        # (t=1 would give 9 and t=4 would give 4: both outside the left interval)
        q_arm_l_7=[9, 0, 0, 0, 2, 0, 0],
        # t=3: |1 - 0 + 7| = 8, t=4: |4 - 2 + 0| = 2, t=5: |4 - 8 + 1| = 3
        q_arm_r_3=[7, 7, 7, 0, 1, 4, 4],
    )
    # left: sum 1 + 1 + 0 + 2 = 4 over 7 joints x 2 centres = 14 terms
    # right: sum 8 + 2 + 3 = 13 over 7 joints x 3 centres = 21 terms
    # pooled: 17 / 35 (the mean of the two arm means would be 0.452, not this)
    assert compute_trial_metrics(trial, False, DEFAULT).smoothness == pytest.approx(17 / 35)


def test_grip_just_below_threshold_breaks_the_window() -> None:
    # left active at t = 0, 2, 3, 4 only (0.4999 < 0.5): the single centre is t = 3
    # arm_l_2 second differences: t=1: |5 - 0 + 0| = 5 and t=2: |5 - 10 + 0| = 5 (both
    # excluded: they touch t=1), t=3: |3 - 10 + 5| = 2
    trial = frames(5, grip_l=[1.0, 0.4999, 1.0, 1.0, 1.0], q_arm_l_2=[0, 0, 5, 5, 3])
    # 2 over 7 joints x 1 centre
    assert compute_trial_metrics(trial, False, DEFAULT).smoothness == pytest.approx(2 / 7)


def test_no_grip_gives_nan_smoothness_and_base_only_activity() -> None:
    trial = frames(
        5,
        q_arm_l_1=[0, 1, 0, 1, 0],  # jerky, but never under grip
        dq_arm_l_1=[1.0] * 5,  # fast, but never under grip
        dq_arm_r_4=[-1.0] * 5,
        base_vx=[0.0, 0.0, 0.5, 0.0, 0.0],  # the base moves in frame 2 only
    )
    result = compute_trial_metrics(trial, False, DEFAULT)
    assert math.isnan(result.smoothness)
    assert result.active_ratio == pytest.approx(1 / 5)


def test_too_few_frames_for_a_second_difference() -> None:
    trial = frames(2, grip_l=[1.0, 1.0], grip_r=[1.0, 1.0])
    assert math.isnan(compute_trial_metrics(trial, False, DEFAULT).smoothness)


def test_active_ratio_frame_by_frame() -> None:
    trial = frames(
        8,
        # f1: 0.03 > 0.02 m/s;  f2: sqrt(0.015^2 + 0.015^2) = 0.0212 > 0.02 m/s
        # (neither component alone exceeds the threshold)
        base_vx=[0, 0.03, 0.015, 0, 0, 0, 0, 0],
        base_vy=[0, 0, 0.015, 0, 0, 0, 0, 0],
        # f3: |-0.06| > 0.05 rad/s;  f4: exactly 0.05 is not > 0.05
        base_wz=[0, 0, 0, -0.06, 0.05, 0, 0, 0],
        # f5: a fast left joint without a left grip: not counted
        # f7: exactly 0.05 rad/s under grip is not > 0.05
        dq_arm_l_2=[0, 0, 0, 0, 0, 0.2, 0, 0],
        dq_arm_l_1=[0, 0, 0, 0, 0, 0, 0, 0.05],
        grip_l=[0, 0, 0, 0, 0, 0, 0, 1.0],
        # f6: |-0.051| > 0.05 under a right grip of exactly 0.5 (>= 0.5: active)
        dq_arm_r_7=[0, 0, 0, 0, 0, 0, -0.051, 0],
        grip_r=[0, 0, 0, 0, 0, 0, 0.5, 0],
    )
    # active frames f1, f2, f3, f6: 4 of 8
    assert compute_trial_metrics(trial, False, DEFAULT).active_ratio == pytest.approx(0.5)


def test_left_grip_does_not_gate_the_right_arm() -> None:
    # the right arm moves fast while only the LEFT grip is held: no frame is active
    trial = frames(4, grip_l=[1.0] * 4, dq_arm_r_1=[0.3] * 4)
    assert compute_trial_metrics(trial, False, DEFAULT).active_ratio == 0.0


def test_base_yaw_alone_makes_frames_active() -> None:
    # frames 1 and 2 turn at 0.1 rad/s with no translation: 2 of 5
    trial = frames(5, base_wz=[0, 0.1, 0.1, 0, 0])
    assert compute_trial_metrics(trial, False, DEFAULT).active_ratio == pytest.approx(0.4)


def test_thresholds_are_configurable() -> None:
    # with a yaw threshold of 0.2 rad/s, 0.1 rad/s is no longer motion; grip 0.9 is now
    # below a grip threshold of 0.95, so the left joint at 1 rad/s no longer counts
    trial = frames(3, base_wz=[0.1, 0, 0], grip_l=[0, 0.9, 0], dq_arm_l_5=[0, 1.0, 0])
    assert compute_trial_metrics(trial, False, DEFAULT).active_ratio == pytest.approx(2 / 3)
    strict = MetricThresholds(grip_threshold=0.95, base_yaw_threshold=0.2)
    assert compute_trial_metrics(trial, False, strict).active_ratio == 0.0

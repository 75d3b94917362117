"""Completion time, sampling, monotonicity and non-finite values on hand-built frames.

Every expected value is worked out by hand in the comments.
"""

from __future__ import annotations

import math
import warnings

import pytest

from tests.metrics.builders import frames
from workcell.metrics import MetricThresholds, TrialMetrics, compute_trial_metrics

DEFAULT = MetricThresholds()
NAN = math.nan
INF = math.inf


def test_completion_time_is_last_t_sim_of_a_success_only() -> None:
    trial = frames(5, t_sim=[0.0, 0.05, 0.1, 0.15, 0.2])
    assert compute_trial_metrics(trial, True, DEFAULT).completion_time_s == 0.2
    assert compute_trial_metrics(trial, False, DEFAULT).completion_time_s is None
    assert compute_trial_metrics(frames(0), True, DEFAULT).completion_time_s is None


def test_one_second_wall_gap_is_found() -> None:
    trial = frames(
        6,
        t_sim=[0.0, 0.25, 0.5, 0.75, 1.0, 1.25],
        t_wall=[1000.0, 1000.25, 1000.5, 1001.5, 1001.75, 1002.0],
    )
    result = compute_trial_metrics(trial, False, DEFAULT)
    assert result.max_gap_s == 1.0  # 1001.5 - 1000.5
    assert result.hz_wall == 2.5  # 5 intervals / 2.0 s
    assert result.hz_sim == 4.0  # 5 intervals / 1.25 s
    assert result.monotonic
    assert result.n_frames == 6


def test_twenty_hz_trial() -> None:
    # 7 frames 0.05 s apart: 6 intervals over 0.30 s = 20 Hz on both clocks
    result = compute_trial_metrics(frames(7), False, DEFAULT)
    assert result.hz_sim == pytest.approx(20.0)
    assert result.hz_wall == pytest.approx(20.0)
    assert result.max_gap_s == pytest.approx(0.05)


def test_repeated_sim_time_is_not_monotonic() -> None:
    trial = frames(5, t_sim=[0.0, 0.05, 0.1, 0.1, 0.15])
    result = compute_trial_metrics(trial, False, DEFAULT)
    assert not result.monotonic
    assert result.hz_sim == pytest.approx(4 / 0.15)  # span first..last still 0.15 s


def test_wall_clock_going_back() -> None:
    trial = frames(5, t_wall=[10.0, 11.0, 10.5, 12.0, 12.5])
    result = compute_trial_metrics(trial, False, DEFAULT)
    assert not result.monotonic
    assert result.max_gap_s == 1.5  # diffs 1.0, -0.5, 1.5, 0.5
    assert result.hz_wall == pytest.approx(4 / 2.5)


def test_backwards_or_zero_span_gives_nan_rate() -> None:
    backwards = frames(3, t_wall=[5.0, 4.0, 3.0], t_sim=[1.0, 1.0, 1.0])
    result = compute_trial_metrics(backwards, False, DEFAULT)
    assert math.isnan(result.hz_wall)  # span -2 s
    assert math.isnan(result.hz_sim)  # span 0 s
    assert result.max_gap_s == -1.0  # every step goes back by 1 s


def test_zero_and_one_frame() -> None:
    empty = compute_trial_metrics(frames(0), False, DEFAULT)
    assert (empty.path_length_m, empty.max_gap_s, empty.monotonic, empty.n_frames) == (
        0.0,
        0.0,
        True,
        0,
    )
    for value in (empty.smoothness, empty.active_ratio, empty.hz_wall, empty.hz_sim):
        assert math.isnan(value)
    assert math.isnan(empty.nonfinite_share)
    one = compute_trial_metrics(frames(1), True, DEFAULT)
    assert one.completion_time_s == 0.0
    assert math.isnan(one.hz_wall)
    assert (one.max_gap_s, one.nonfinite_share, one.active_ratio) == (0.0, 0.0, 0.0)


def _quietly(trial_frames: int, **given: list[float]) -> TrialMetrics:
    """Metrics computed with every numpy warning turned into an error."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        return compute_trial_metrics(frames(trial_frames, **given), False, DEFAULT)


def test_nonfinite_share_counts_frames_not_values() -> None:
    result = _quietly(
        5,
        q_arm_r_4=[0, NAN, 0, 0, 0],  # frame 1
        t_wall=[0, INF, 2, 3, 4],  # frame 1 again: still one frame
        grip_l=[0, 0, 0, -INF, 0],  # frame 3
    )
    assert result.nonfinite_share == pytest.approx(2 / 5)
    assert not result.monotonic  # inf then 2 goes back
    assert math.isinf(result.max_gap_s)  # inf - 0


def test_nan_tcp_makes_path_nan_without_warnings() -> None:
    result = _quietly(4, tcp_l_x=[0, 1, NAN, 3], tcp_r_z=[0, INF, 0, 0])
    assert math.isnan(result.path_length_m)
    assert result.nonfinite_share == pytest.approx(2 / 4)


def test_nan_grip_is_inactive_and_nan_speed_is_still() -> None:
    # grip NaN at t=2 breaks the window: no centre has three active grips
    # base_vx NaN and base_wz NaN do not count as motion; frame 3's 0.1 rad/s does
    result = _quietly(
        5,
        grip_l=[1, 1, NAN, 1, 1],
        q_arm_l_1=[0, 5, 0, 5, 0],
        dq_arm_l_1=[0, 0, 1.0, 0, 0],  # fast at t=2, but the grip there is NaN
        base_vx=[NAN, 0, 0, 0, 0],
        base_wz=[0, NAN, 0, 0.1, 0],
    )
    assert math.isnan(result.smoothness)  # no gated term at all
    assert result.active_ratio == pytest.approx(1 / 5)


def test_nan_joint_inside_a_grip_window_makes_smoothness_nan() -> None:
    inside = _quietly(4, grip_r=[1, 1, 1, 1], q_arm_r_2=[0, NAN, 0, 0])
    assert math.isnan(inside.smoothness)


def test_nan_joint_outside_every_grip_window_is_ignored() -> None:
    # right grip active at t = 2..4: the only centre is t = 3; q at t = 0 is NaN but not used
    # arm_r_6 at t=3: |4 - 2 + 0| = 2 over 7 joints x 1 centre
    outside = _quietly(5, grip_r=[0, 0, 1, 1, 1], q_arm_r_6=[NAN, 0, 0, 1, 4])
    assert outside.smoothness == pytest.approx(2 / 7)


def test_nan_time_stamps() -> None:
    result = _quietly(4, t_sim=[0, NAN, 0.1, 0.15], t_wall=[0, 1, 2, NAN])
    assert not result.monotonic
    assert math.isnan(result.max_gap_s)
    assert math.isnan(result.hz_wall)
    assert result.hz_sim == pytest.approx(3 / 0.15)  # first and last t_sim are finite

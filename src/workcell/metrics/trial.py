"""Trial-level metrics computed from one trial's frames alone (docs/architecture.md "Metrics").

Vectorised over frames: no per-frame Python. Non-finite inputs never raise; what they
produce is stated per metric in :data:`~workcell.metrics.definitions.METRIC_DEFINITIONS`
(in short: sums and means that touch a non-finite value become NaN, comparisons with a
non-finite grip or speed are false, so it counts as inactive / not moving).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from workcell.metrics.definitions import MetricThresholds
from workcell.metrics.frames import FloatArray, FrameArrays

BoolArray = npt.NDArray[np.bool_]


@dataclass(frozen=True)
class TrialMetrics:
    """One trial's metrics; field names are the trials.csv column names.

    ``completion_time_s`` (s, None unless successful), ``path_length_m`` (m), ``smoothness``
    (rad/sample^2), ``active_ratio`` and ``nonfinite_share`` (shares 0-1), ``hz_wall`` and
    ``hz_sim`` (Hz), ``max_gap_s`` (s), ``monotonic`` and ``n_frames``.
    """

    completion_time_s: float | None
    path_length_m: float
    smoothness: float
    active_ratio: float
    hz_wall: float
    hz_sim: float
    max_gap_s: float
    nonfinite_share: float
    monotonic: bool
    n_frames: int


def _path_length(tcp_l: FloatArray, tcp_r: FloatArray) -> float:
    """Metres travelled by the TCP midpoint, summed over consecutive frames."""
    if len(tcp_l) < 2:
        return 0.0
    doubled = tcp_l + tcp_r  # 2 m_t
    step = doubled[1:] - doubled[:-1]
    return 0.5 * float(np.sqrt((step * step).sum(axis=1)).sum())


def _gated_second_differences(q: FloatArray, active: BoolArray) -> tuple[float, int]:
    """Sum of |second differences| (rad/sample^2) of one arm where its grip is active at
    t-1, t and t+1, and the number of (joint, t) terms summed."""
    if len(q) < 3:
        return 0.0, 0
    gate = active[:-2] & active[1:-1] & active[2:]
    rows = int(np.count_nonzero(gate))
    if rows == 0:
        return 0.0, 0
    per_frame = np.abs(q[2:] - 2.0 * q[1:-1] + q[:-2]).sum(axis=1)
    return float(per_frame[gate].sum()), rows * q.shape[1]


def _smoothness(frames: FrameArrays, active_l: BoolArray, active_r: BoolArray) -> float:
    """Pooled mean over both arms of the grip-gated |second differences| (rad/sample^2)."""
    sum_l, count_l = _gated_second_differences(frames.q_l, active_l)
    sum_r, count_r = _gated_second_differences(frames.q_r, active_r)
    count = count_l + count_r
    return (sum_l + sum_r) / count if count else math.nan


def _active_ratio(
    frames: FrameArrays, thresholds: MetricThresholds, active_l: BoolArray, active_r: BoolArray
) -> float:
    """Share of frames in which the base moves or an arm moves under an active grip."""
    n = len(frames)
    if n == 0:
        return math.nan
    vx, vy, wz = frames.base_v[:, 0], frames.base_v[:, 1], frames.base_v[:, 2]
    moving = np.hypot(vx, vy) > thresholds.base_linear_threshold
    moving |= np.abs(wz) > thresholds.base_yaw_threshold
    rate = thresholds.joint_rate_threshold
    moving |= active_l & (np.abs(frames.dq_l) > rate).any(axis=1)
    moving |= active_r & (np.abs(frames.dq_r) > rate).any(axis=1)
    return int(np.count_nonzero(moving)) / n


def _hz(t: FloatArray) -> float:
    """Realised rate (Hz) over the span first..last frame; NaN without a positive span."""
    if len(t) < 2:
        return math.nan
    span = float(t[-1] - t[0])
    return (len(t) - 1) / span if math.isfinite(span) and span > 0 else math.nan


def _strictly_increasing(t: FloatArray) -> bool:
    return bool(np.all(t[1:] > t[:-1]))


def _nonfinite_share(frames: FrameArrays) -> float:
    """Share of frames with any NaN or infinite value in any of the frame arrays."""
    n = len(frames)
    if n == 0:
        return math.nan
    finite = np.isfinite(frames.t_sim) & np.isfinite(frames.t_wall)
    finite &= np.isfinite(frames.grip_l) & np.isfinite(frames.grip_r)
    for block in (frames.base_v, frames.tcp_l, frames.tcp_r):
        finite &= np.isfinite(block).all(axis=1)
    for block in (frames.q_l, frames.q_r, frames.dq_l, frames.dq_r):
        finite &= np.isfinite(block).all(axis=1)
    return (n - int(np.count_nonzero(finite))) / n


def compute_trial_metrics(
    frames: FrameArrays, success: bool, thresholds: MetricThresholds
) -> TrialMetrics:
    """Every trial-level metric of one trial, as docs/architecture.md defines them.

    ``success`` says whether the trial ended in success: only then is
    ``completion_time_s`` the ``t_sim`` (s) of the last frame (None without frames).
    """
    n = len(frames)
    with np.errstate(all="ignore"):  # non-finite inputs give NaN results, not warnings
        active_l = frames.grip_l >= thresholds.grip_threshold
        active_r = frames.grip_r >= thresholds.grip_threshold
        return TrialMetrics(
            completion_time_s=float(frames.t_sim[-1]) if success and n else None,
            path_length_m=_path_length(frames.tcp_l, frames.tcp_r),
            smoothness=_smoothness(frames, active_l, active_r),
            active_ratio=_active_ratio(frames, thresholds, active_l, active_r),
            hz_wall=_hz(frames.t_wall),
            hz_sim=_hz(frames.t_sim),
            max_gap_s=float(np.max(np.diff(frames.t_wall))) if n >= 2 else 0.0,
            nonfinite_share=_nonfinite_share(frames),
            monotonic=_strictly_increasing(frames.t_sim) and _strictly_increasing(frames.t_wall),
            n_frames=n,
        )

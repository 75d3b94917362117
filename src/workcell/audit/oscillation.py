"""Sustained arm oscillation: a joint swinging back and forth, fast, for seconds.

Definition (version :data:`OSCILLATION_VERSION`), per arm joint j of both arms, on the
session's frame grid of rate R (Hz):

1. High-pass: r_t = q_t - (centred moving average of q over L = odd round(R / f_min)
   frames). Steady motion (a ramp is removed exactly) leaves little; an oscillation at
   f >= f_min passes with gain |H(f)| = |1 - D_L(f)| >= H_min, D_L the moving average's
   response.
2. Turning points: frames where the sign of r_(t+1) - r_t reverses (a zero step keeps the
   previous sign). Between consecutive turning points lies a half-swing: its size is the
   difference of r at its ends, its length the number of frames between them.
3. A half-swing qualifies when its size >= swing_threshold_rad, it lasts at most
   ceil(R / (2 f_min)) + 1 frames (frequency >= f_min, one frame of slack for where
   sampling puts a turning point) and the joint's arm has its grip active over all of it.
4. Steadiness (version 2): within each run of consecutive qualifying half-swings, a
   half-swing whose size is not within a factor SWING_SPREAD (2) of the run's median
   size, or whose length differs from the run's median length by more than
   PERIOD_SPREAD (50 %) plus one frame, does not qualify: deliberate moves between task
   phases reverse a joint too, but not with a steady size and rhythm.
5. The trial is flagged when, for some joint, consecutive qualifying half-swings span at
   least min_duration_s seconds of frames.

The swing threshold is derived so that the documented bound holds: every sinusoidal
oscillation of amplitude >= amplitude_rad at a frequency from f_min to f_guaranteed
(capped at R/4) sustained long enough, under an active grip, is flagged:
swing_threshold_rad = 2 * amplitude_rad * H_min * cos(pi * f_guaranteed / R) (the sampled
peak-to-peak of such a sine is at least that). Faster oscillations up to R/2 are flagged
when their sampled swings exceed the threshold.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from workcell.audit.flags import ARM_OSCILLATION, Flag
from workcell.checks import positive
from workcell.errors import ConfigError
from workcell.metrics import FrameArrays
from workcell.sim.joints import arm_joint_names

OSCILLATION_VERSION = "2"
"""Bumped whenever the definition above changes meaning."""

JOINT_NAMES: tuple[str, ...] = (*arm_joint_names("l"), *arm_joint_names("r"))
BoolArray = npt.NDArray[np.bool_]
IntArray = npt.NDArray[np.intp]


@dataclass(frozen=True)
class OscillationParams:
    """Documented bounds: frequencies in Hz, amplitude in rad, duration in s."""

    min_frequency_hz: float = 1.5
    guaranteed_max_frequency_hz: float = 5.0
    amplitude_rad: float = 0.02
    min_duration_s: float = 2.0
    disqualifying: bool = True

    def __post_init__(self) -> None:
        problems = positive("oscillation.min_frequency_hz", self.min_frequency_hz, "Hz")
        problems += positive("oscillation.amplitude_rad", self.amplitude_rad, "rad")
        problems += positive("oscillation.min_duration_s", self.min_duration_s, "s")
        if not self.guaranteed_max_frequency_hz > self.min_frequency_hz:
            problems.append(
                f"oscillation.guaranteed_max_frequency_hz = {self.guaranteed_max_frequency_hz:g}"
                ": must exceed min_frequency_hz"
            )
        if problems:
            raise ConfigError(problems)


def _moving_average_gain(window: int, rate_hz: float, f: npt.NDArray[np.float64]) -> Any:
    """Response of a centred moving average of ``window`` frames at frequencies ``f``."""
    x = np.pi * f / rate_hz
    return np.sin(window * x) / (window * np.sin(x))


@dataclass(frozen=True)
class OscillationCriteria:
    """The criteria of :class:`OscillationParams` on a grid of ``rate_hz`` frames/s."""

    rate_hz: float
    window_frames: int
    max_half_swing_frames: int
    min_span_frames: int
    guaranteed_max_frequency_hz: float
    highpass_min_gain: float
    swing_threshold_rad: float

    @classmethod
    def of(cls, params: OscillationParams, rate_hz: float) -> OscillationCriteria | None:
        """None when the rate is too low to resolve f_min (R < 4 f_min)."""
        f_high = min(params.guaranteed_max_frequency_hz, rate_hz / 4)
        if params.min_frequency_hz >= f_high:
            return None
        window = round(rate_hz / params.min_frequency_hz)
        window += 1 - window % 2
        band = np.linspace(params.min_frequency_hz, f_high, 512)
        gain = float(np.min(np.abs(1.0 - _moving_average_gain(window, rate_hz, band))))
        return cls(
            rate_hz=rate_hz,
            window_frames=window,
            max_half_swing_frames=math.ceil(rate_hz / (2 * params.min_frequency_hz)) + 1,
            min_span_frames=math.ceil(params.min_duration_s * rate_hz - 1e-9),
            guaranteed_max_frequency_hz=f_high,
            highpass_min_gain=gain,
            swing_threshold_rad=2
            * params.amplitude_rad
            * gain
            * math.cos(math.pi * f_high / rate_hz),
        )

    def describe(self) -> dict[str, float | int]:
        return asdict(self)


SWING_SPREAD = 2.0
"""Within one oscillation, every half-swing is within this factor of the median swing."""
PERIOD_SPREAD = 0.5
"""... and its length within this fraction (plus one frame of sampling slack) of the
median half-swing length."""


def _runs(ok: BoolArray) -> tuple[IntArray, IntArray]:
    """Start and end (exclusive) of every run of True in ``ok``."""
    edges = np.diff(np.concatenate([[0], ok.astype(np.int8), [0]]))
    return np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)


def _turning_points(resid: npt.NDArray[np.float64]) -> tuple[IntArray, IntArray]:
    """(row, column) of every turning point of the (joints, frames) residual, sorted by
    row then column; a zero step keeps the sign of the step before it."""
    k, m = resid.shape
    step = np.sign(resid[:, 1:] - resid[:, :-1])  # step[:, j]: j -> j + 1
    if not step.all():  # zero steps: carry the sign of the step before
        sign = np.zeros((k, m))
        sign[:, 1:] = step
        last = np.where(sign != 0, np.arange(m), 0)
        np.maximum.accumulate(last, axis=1, out=last)
        last += np.arange(0, k * m, m)[:, None]
        step = sign.ravel()[last.ravel()].reshape(k, m)[:, 1:]
    rows, cols = np.nonzero(step[:, 1:] * step[:, :-1] < 0)
    return rows, cols + 1  # a turn at residual column j + 1


def detect_oscillation(
    frames: FrameArrays,
    active_l: BoolArray,
    active_r: BoolArray,
    criteria: OscillationCriteria,
    disqualifying: bool,
) -> Flag | None:
    """The ``arm_oscillation`` flag of one trial, or None. ``active_*`` mark the frames
    whose grip is active (grip >= the session's grip threshold)."""
    n, window = len(frames), criteria.window_frames
    if n < window + 2:
        return None
    half = window // 2
    with np.errstate(invalid="ignore"):
        q = np.concatenate([frames.q_l.T, frames.q_r.T])  # (14, n), one joint per row
        sums = np.zeros((q.shape[0], n + 1))
        np.cumsum(q, axis=1, out=sums[:, 1:])
        resid = q[:, half : n - half] - (sums[:, window:] - sums[:, :-window]) / window
        row, at = _turning_points(resid)
        if len(at) < 2:
            return None
        same = row[1:] == row[:-1]
        ext = resid[row, at]
        swing = np.abs(ext[1:] - ext[:-1])
        length = at[1:] - at[:-1]
        ok = same & (swing >= criteria.swing_threshold_rad)
        ok &= length <= criteria.max_half_swing_frames
    if not ok.any():
        return None
    inactive = np.zeros((2, n + 1), dtype=np.int64)
    np.cumsum(~active_l, out=inactive[0, 1:])
    np.cumsum(~active_r, out=inactive[1, 1:])
    arm = (row[1:] >= frames.q_l.shape[1]).astype(np.intp)
    ok &= inactive[arm, at[1:] + half + 1] == inactive[arm, at[:-1] + half]
    starts, ends = _runs(ok)
    if len(starts) == 0:
        return None
    # An oscillation swings steadily: within a run, a half-swing far from the run's
    # median size (a deliberate move between phases) breaks it.
    for s, e in zip(starts, ends, strict=True):
        size, period = float(np.median(swing[s:e])), float(np.median(length[s:e]))
        steady = (swing[s:e] >= size / SWING_SPREAD) & (swing[s:e] <= size * SWING_SPREAD)
        steady &= np.abs(length[s:e] - period) <= PERIOD_SPREAD * period + 1
        ok[s:e] &= steady
    starts, ends = _runs(ok)
    if len(starts) == 0:
        return None
    spans = at[ends] - at[starts]
    best = int(np.argmax(spans))
    if spans[best] < criteria.min_span_frames:
        return None
    start, end = int(starts[best]), int(ends[best])
    seconds = spans[best] / criteria.rate_hz
    count = end - start
    t_start = float(frames.t_sim[at[start] + half])
    detail = (
        f"{JOINT_NAMES[row[start]]}: {count} alternating swings of >= "
        f"{criteria.swing_threshold_rad:.4f} rad over {seconds:.2f} s from t_sim "
        f"{t_start:.2f} s (about {count / (2 * seconds):.1f} Hz)"
    )
    return Flag(ARM_OSCILLATION, detail, disqualifying)

"""Sampling continuity: gaps between frames and timestamps that do not increase.

Definition (version :data:`SAMPLING_VERSION`): with the session's frame rate R (Hz), a gap
is an interval between consecutive frames longer than ``gap_periods / R`` seconds on the
sim clock (``t_sim``, dropped frames) or, in a trial recorded in real time, on the wall
clock (``t_wall``, a stall the operator lived through); any gap raises ``sampling_gap``. A
trial is recorded in real time when its wall clock advanced at least
``real_time_share`` as fast as its sim clock over the trial (a paced session, as ``workcell
serve`` runs); a headless run at full speed (``workcell collect``: the sim runs ahead of the
wall clock) has no wall-clock gaps, since a pause of the machine there is no pause in the
demonstration. ``non_monotonic`` is raised when ``t_sim`` or ``t_wall``
does not strictly increase from some frame to the next (DESIGN's ``monotonic`` metric).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from workcell.audit.flags import NON_MONOTONIC, SAMPLING_GAP, Flag
from workcell.checks import positive
from workcell.errors import ConfigError
from workcell.metrics import FrameArrays

SAMPLING_VERSION = "2"
"""Bumped whenever the definition above changes meaning."""


@dataclass(frozen=True)
class SamplingParams:
    """``gap_periods``: a gap is longer than this many frame periods. Whether each flag
    disqualifies a successful trial (the paper keeps trials with gaps up to 0.985 s)."""

    gap_periods: float = 5.0
    gap_disqualifying: bool = False
    non_monotonic_disqualifying: bool = True
    real_time_share: float = 0.5
    """A trial is recorded in real time when wall time / sim time >= this over the trial."""

    def __post_init__(self) -> None:
        problems = positive("sampling.gap_periods", self.gap_periods, "frame periods")
        problems += positive("sampling.real_time_share", self.real_time_share, "")
        if problems:
            raise ConfigError(problems)


def _gaps(t: np.ndarray, limit: float) -> tuple[int, int, float]:
    """(number of gaps, frame after the largest, its length in s); NaN steps are no gap."""
    step = np.diff(t)
    with np.errstate(invalid="ignore"):
        over = np.flatnonzero(step > limit)
    if len(over) == 0:
        return 0, -1, 0.0
    worst = int(over[np.argmax(step[over])])
    return len(over), worst + 1, float(step[worst])


def _first_not_increasing(t: np.ndarray) -> int:
    """Index of the first frame not later than the one before it, or -1."""
    with np.errstate(invalid="ignore"):
        bad = np.flatnonzero(~(t[1:] > t[:-1]))
    return int(bad[0]) + 1 if len(bad) else -1


def recorded_in_real_time(frames: FrameArrays, share: float) -> bool:
    """Whether the wall clock advanced at least ``share`` as fast as the sim clock over
    the trial (True when either span is unknown or zero: nothing says otherwise)."""
    t_sim, t_wall = frames.t_sim, frames.t_wall
    finite_sim, finite_wall = t_sim[np.isfinite(t_sim)], t_wall[np.isfinite(t_wall)]
    if len(finite_sim) < 2 or len(finite_wall) < 2:
        return True
    sim = float(finite_sim[-1] - finite_sim[0])
    wall = float(finite_wall[-1] - finite_wall[0])
    return sim <= 0 or wall >= share * sim


def detect_sampling(frames: FrameArrays, rate_hz: float, params: SamplingParams) -> list[Flag]:
    """The ``sampling_gap`` and ``non_monotonic`` flags of one trial (possibly none)."""
    flags: list[Flag] = []
    limit = params.gap_periods / rate_hz
    found = []
    clocks = [("t_sim", frames.t_sim)]
    if recorded_in_real_time(frames, params.real_time_share):
        clocks.insert(0, ("t_wall", frames.t_wall))
    for clock, t in clocks:
        count, at, length = _gaps(t, limit)
        if count:
            found.append(f"{clock}: {count} gap(s), largest {length:.3f} s before frame {at}")
    if found:
        detail = "; ".join(found) + f" (limit {limit:.3f} s = {params.gap_periods:g} periods)"
        flags.append(Flag(SAMPLING_GAP, detail, params.gap_disqualifying))
    broken = []
    for clock, t in (("t_sim", frames.t_sim), ("t_wall", frames.t_wall)):
        at = _first_not_increasing(t)
        if at >= 0:
            broken.append(f"{clock} does not increase at frame {at}")
    if broken:
        flags.append(Flag(NON_MONOTONIC, "; ".join(broken), params.non_monotonic_disqualifying))
    return flags

"""Sampling continuity: gaps between frames and timestamps that do not increase.

Definition (version :data:`SAMPLING_VERSION`): with the session's frame rate R (Hz), a gap
is an interval between consecutive frames longer than ``gap_periods / R`` seconds on the
sim clock (``t_sim``, dropped frames) or, in a trial recorded in real time, on the wall
clock (``t_wall``, a stall the operator lived through); any gap raises ``sampling_gap``. A
trial is recorded in real time when its sim clock never ran ahead of its wall clock, both
counted from the trial's first frame, by more than ``ahead_tolerance_s``: a paced session
(``workcell serve``) steps the simulation only once the wall clock has reached it, so it
never gets ahead, while a headless run (``workcell collect``, the env) runs ahead whenever
the machine lets it. A wall-clock gap in a headless run is a pause of the machine, not of
the demonstration, and is not counted. (Version 2 compared the trial's overall wall and
sim spans; a headless run on a busy machine can be as slow as real time overall, and its
machine's pauses were flagged.) ``non_monotonic`` is raised when ``t_sim`` or ``t_wall``
does not strictly increase from some frame to the next (the ``monotonic`` metric of
docs/architecture.md). The operator's pauses (``paused``/``resumed`` events) are not gaps:
the wall seconds of each pause are taken out of the wall clock of the frames after it
before gaps are looked for (version 4; the ``max_gap_s`` and ``hz_wall`` metrics keep the
wall clock as recorded).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from workcell.audit.flags import NON_MONOTONIC, SAMPLING_GAP, Flag
from workcell.checks import positive
from workcell.errors import ConfigError
from workcell.metrics import FrameArrays

SAMPLING_VERSION = "4"
"""Bumped whenever the definition above changes meaning."""
PAUSE_INSTANT_S = 1e-9
"""Frames at a pause's own instant were recorded before it."""


@dataclass(frozen=True)
class SamplingParams:
    """``gap_periods``: a gap is longer than this many frame periods. Whether each flag
    disqualifies a successful trial (the paper keeps trials with gaps up to 0.985 s)."""

    gap_periods: float = 5.0
    gap_disqualifying: bool = False
    non_monotonic_disqualifying: bool = True
    ahead_tolerance_s: float = 1.0
    """A trial whose sim clock got further ahead of its wall clock than this (s) was not
    recorded in real time."""

    def __post_init__(self) -> None:
        problems = positive("sampling.gap_periods", self.gap_periods, "frame periods")
        problems += positive("sampling.ahead_tolerance_s", self.ahead_tolerance_s, "s")
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


def recorded_in_real_time(frames: FrameArrays, ahead_tolerance_s: float) -> bool:
    """Whether the sim clock stayed within ``ahead_tolerance_s`` of the wall clock (never
    further ahead), both counted from the trial's first frame with both clocks finite
    (True when that cannot be told: nothing says otherwise)."""
    t_sim, t_wall = frames.t_sim, frames.t_wall
    both = np.isfinite(t_sim) & np.isfinite(t_wall)
    if np.count_nonzero(both) < 2:
        return True
    sim, wall = t_sim[both], t_wall[both]
    ahead = (sim - sim[0]) - (wall - wall[0])
    return float(np.max(ahead)) <= ahead_tolerance_s


def without_pauses(frames: FrameArrays, pauses: Sequence[tuple[float, float]]) -> FrameArrays:
    """``frames`` with each pause's wall seconds taken out of the wall clock of every frame
    after it (``pauses``: (t_sim it paused at, seconds it stood), as recorded)."""
    if not pauses:
        return frames
    t_wall = frames.t_wall.copy()
    for at, seconds in pauses:
        with np.errstate(invalid="ignore"):
            t_wall[frames.t_sim > at + PAUSE_INSTANT_S] -= seconds
    return dataclasses.replace(frames, t_wall=t_wall)


def detect_sampling(
    frames: FrameArrays,
    rate_hz: float,
    params: SamplingParams,
    pauses: Sequence[tuple[float, float]] = (),
) -> list[Flag]:
    """The ``sampling_gap`` and ``non_monotonic`` flags of one trial (possibly none);
    ``pauses``: the operator's, not counted as gaps on the wall clock."""
    flags: list[Flag] = []
    frames = without_pauses(frames, pauses)
    limit = params.gap_periods / rate_hz
    found = []
    clocks = [("t_sim", frames.t_sim)]
    if recorded_in_real_time(frames, params.ahead_tolerance_s):
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

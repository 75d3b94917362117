"""Admission by measured headroom: a session starts only while the machine can run one more
at real time; otherwise its start waits in line, and starts by itself once there is room.

The rule (``workcell serve``; docs/architecture.md, "Admission"): with ``n`` sessions
running, one more is admitted when

1. every measured running session's recent real-time factor (simulated over wall
   seconds, pauses left out, over the latest :data:`~workcell.task.pacing.RECENT_WINDOW_S`
   seconds) is at least ``min_real_time_factor`` (0.98 by default: a margin over the 0.95
   a session must keep), and
2. the cores a session uses (the mean over the measured running sessions of their
   processes' CPU seconds per wall second over that window; :data:`UNMEASURED_CORES`
   while none is measured yet) times ``n + 1`` fit the ``cores`` budget (the machine's
   cores by default, ``--admit-cores``).

A session is measured once its first window has passed. No session running: always
admitted. The store's writer process and the server's own work
are not in a session's figure; the margin of rule 2 is there for them. A session in a Ray
actor is measured alike, on the cores of its node: ``cores`` then is the cluster's.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from dataclasses import dataclass

MIN_REAL_TIME_FACTOR = 0.98
"""Default least recent real-time factor of every running session for one more to start
(``ServerOptions.admit_min_real_time_factor``)."""
UNMEASURED_CORES = 1.0
"""The cores a session is counted at while no running session has been measured."""
BEHIND_REAL_TIME = 0.95
"""Below this real-time factor a session is behind real time (its trials are flagged
``sampling_gap``): the admin page says so in words."""


@dataclass(frozen=True)
class Measured:
    """One running session's recent figures (:class:`~workcell.task.pacing.PacingStats`)."""

    real_time_factor: float
    cores: float


@dataclass(frozen=True)
class AdmissionRule:
    cores: float
    """The cores the sessions may use together."""
    min_real_time_factor: float = MIN_REAL_TIME_FACTOR

    @classmethod
    def of_machine(cls, cores: float | None, min_real_time_factor: float) -> AdmissionRule:
        """The rule with ``cores`` (None: this machine's, ``os.cpu_count()``)."""
        return cls(float(cores or os.cpu_count() or 1), min_real_time_factor)

    def refuses(self, running: Sequence[Measured | None]) -> str | None:
        """Why one more session may not start now, in words (None: it may); ``running``
        holds each running session's figures, None for one not yet measured."""
        n = len(running)
        if n == 0:
            return None
        measured = [m for m in running if m is not None]
        least = self.min_real_time_factor
        slow = [m.real_time_factor for m in measured if m.real_time_factor < least]
        if slow:
            return (
                f"{len(slow)} running session(s) at {min(slow):.2f}x real time, below the "
                f"{self.min_real_time_factor:.2f}x needed to start one more"
            )
        per_session = (
            sum(m.cores for m in measured) / len(measured) if measured else UNMEASURED_CORES
        )
        needed = per_session * (n + 1)
        if needed > self.cores:
            assumed = "" if measured else " (assumed until a session is measured)"
            return (
                f"{n + 1} sessions at {per_session:.2f} cores each{assumed} need "
                f"{needed:.2f} cores; this machine gives the sessions {self.cores:g}"
            )
        return None


def behind_real_time(factors: Sequence[float]) -> str:
    """The admin page's warning when running sessions fall behind real time ("" when none
    do): "2 sessions are running at 0.85x real time: trials are flagged sampling_gap"."""
    behind = [f for f in factors if 0 < f < BEHIND_REAL_TIME]
    if not behind:
        return ""
    count = f"{len(behind)} sessions are" if len(behind) > 1 else "1 session is"
    return (
        f"{count} running at {min(behind):.2f}x real time: trials are flagged sampling_gap; "
        "stop or pause a session, or run fewer at once"
    )

"""Where an audit reads from: a store or a CSV export, behind one small protocol.

A source hands over sessions, trials and annotations whole (they are small) and frames one
trial at a time, as :class:`~workcell.metrics.FrameArrays` of the columns the metrics need,
so memory does not grow with the number of trials.
"""

from __future__ import annotations

import json
import math
from collections.abc import Collection, Iterator
from pathlib import Path
from typing import Any, Literal, Protocol

import numpy as np
import numpy.typing as npt

from workcell.audit.rows import SessionRow, TrialRow
from workcell.audit.task_stages import StageFrames
from workcell.metrics import REQUIRED_COLUMNS, FrameArrays
from workcell.record.entries import AnnotationRecord

FloatArray = npt.NDArray[np.float64]

FRAME_COLUMNS_READ: tuple[str, ...] = REQUIRED_COLUMNS
"""The frame columns an audit reads: exactly those the metrics and detectors use."""

MIDPOINT_COLUMNS: tuple[str, ...] = ("tcp_l_x", "tcp_l_y", "tcp_r_x", "tcp_r_y")
"""The frame columns of the floor-plane (x-y) TCP-midpoint trajectory."""

SourceKind = Literal["store", "csv"]
Pauses = tuple[tuple[float, float], ...]
"""A trial's pauses: (t_sim it paused at, wall seconds it stood paused), in order."""
Switches = tuple[tuple[str, float], ...]
"""A trial's take-overs and hand-backs: (``take_over`` or ``hand_back``, t_sim), in order."""
SWITCH_KINDS: tuple[str, ...] = ("take_over", "hand_back")


def pause_of(t_sim: object, payload_json: str) -> tuple[float, float] | None:
    """One pause from a ``resumed`` event's time and stored payload (None: unreadable)."""
    try:
        seconds = json.loads(payload_json).get("paused_s")
        at = float(t_sim)  # type: ignore[arg-type]
    except (ValueError, TypeError, AttributeError):
        return None
    if isinstance(seconds, bool) or not isinstance(seconds, int | float):
        return None
    return (at, float(seconds)) if math.isfinite(at) and math.isfinite(seconds) else None


class AuditSource(Protocol):
    """What the audit reads. Frames come in the source's own order; a trial without frames
    may be left out of :meth:`frames`."""

    @property
    def kind(self) -> SourceKind: ...

    @property
    def path(self) -> Path: ...

    def sessions(self) -> list[SessionRow]: ...

    def trials(self) -> list[TrialRow]: ...

    def annotations(self) -> list[AnnotationRecord]: ...

    def frames(self) -> Iterator[tuple[str, FrameArrays]]:
        """(trial_id, frames) for every trial with frames, one trial in memory at a time."""
        ...

    def midpoints(self, trial_ids: Collection[str]) -> dict[str, FloatArray]:
        """The (n, 2) floor-plane TCP midpoints (x, y in metres) of the given trials."""
        ...

    def stage_frames(self, trial_ids: Collection[str]) -> dict[str, StageFrames]:
        """The touches and holds of the given trials (:mod:`workcell.audit.task_stages`)."""
        ...

    def trial_conditions(self, trial_ids: Collection[str]) -> dict[str, dict[str, object]]:
        """The given trials' recorded conditions (their trial_started events')."""
        ...

    def trial_pauses(self, trial_ids: Collection[str]) -> dict[str, Pauses]:
        """The operator's pauses of the given trials that had any (their resumed events':
        the trial time each paused at and the wall seconds it stood)."""
        ...

    def trial_switches(self, trial_ids: Collection[str]) -> dict[str, Switches]:
        """The take-overs and hand-backs of the given trials that had any (their
        ``take_over`` and ``hand_back`` events, in order)."""
        ...

    def close(self) -> None: ...


def midpoint_xy(matrix: npt.NDArray[Any]) -> FloatArray:
    """(n, 2) TCP midpoints from an (n, 4) matrix of MIDPOINT_COLUMNS."""
    data = np.asarray(matrix, dtype=np.float64).reshape(-1, len(MIDPOINT_COLUMNS))
    return 0.5 * (data[:, 0:2] + data[:, 2:4])

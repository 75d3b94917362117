"""What a writing :class:`~workcell.record.store.Store` keeps track of (the sessions and
trials it opened), the rows it writes when they start and end, and how the frame rows it
is handed are numbered and checked."""

from __future__ import annotations

import time
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from workcell.metrics.frames import REQUIRED_COLUMNS
from workcell.record.batch import RowBatch
from workcell.record.entries import (
    FLAG_SEPARATOR,
    SessionInfo,
    StoredMetrics,
    TrialEnd,
    TrialStart,
    to_json,
)
from workcell.record.errors import RecordError
from workcell.record.inclusion import incomplete_reason
from workcell.record.schema import FRAMES, SCHEMA_VERSION, SESSIONS, TRIALS


@dataclass
class Running:
    """A session or trial this store opened and has not closed (mutable bookkeeping)."""

    session_id: str
    next_index: int = 0
    """trials: next frame_index; sessions: next trial_index."""
    next_seq: int = 0
    trial_id: str | None = None
    metric_rows: list[NDArray[np.float64]] = field(default_factory=list)
    """trials: the metric columns of the frames added, in batches."""
    start_row: RowBatch | None = None
    """trials: the trial's row as started, written again when a failed transaction took it
    with it (:func:`~workcell.record.failure.close_after_failure`)."""

    def metric_matrix(self) -> NDArray[np.float64]:
        """(next_index, len(REQUIRED_COLUMNS)): the metric columns of the trial's frames."""
        if not self.metric_rows:
            return np.zeros((0, len(REQUIRED_COLUMNS)))
        return np.concatenate(self.metric_rows)[: self.next_index]


def session_row(session_id: str, info: SessionInfo) -> RowBatch:
    """The row of a session as it starts (status ``running``)."""
    row = {
        "session_id": session_id,
        "created_wall": time.time(),
        "ended_wall": None,
        "schema_version": SCHEMA_VERSION,
        "software_version": info.software_version,
        "mode": info.mode,
        "operator_id": info.operator_id,
        "seed": info.seed,
        "parameters_json": to_json(info.parameters, "session parameters"),
        "thresholds_json": to_json(info.thresholds, "session thresholds"),
        "joint_order_json": to_json(list(info.joint_order), "session joint_order"),
        "metric_definitions_json": to_json(info.metric_definitions, "metric_definitions"),
        "metrics_version": info.metrics_version,
        "status": "running",
        "content_checksum": None,
    }
    return RowBatch.from_mappings(SESSIONS, [row])


def trial_row(session_id: str, trial_id: str, trial_index: int, start: TrialStart) -> RowBatch:
    """The row of a trial as it starts (the columns its end fills are NULL)."""
    row: dict[str, object] = dict.fromkeys(TRIALS.names)
    row |= {
        "session_id": session_id,
        "trial_id": trial_id,
        "trial_index": trial_index,
        "mode": start.mode,
        "round": start.round,
        "level": start.level,
        "required_boxes": start.required_boxes,
        "time_limit_s": start.time_limit_s,
        "trial_seed": start.trial_seed,
        "started_wall": time.time(),
        **start.task_columns(),
    }
    return RowBatch.from_mappings(TRIALS, [row])


def end_columns(end: TrialEnd, m: StoredMetrics) -> dict[str, object]:
    """The trial row's columns written when it closes (``m``: its metrics). An interrupted
    trial is incomplete and never included (:mod:`workcell.record.inclusion`; the reason
    ``incomplete: interrupted (<why>)`` unless the caller gave one)."""
    included, reason = end.included, end.exclusion_reason
    if end.outcome == "interrupted":
        included = False
        reason = reason or incomplete_reason(end.outcome, end.interruption_reason)
    return {
        "outcome": end.outcome,
        "interruption_reason": end.interruption_reason,
        "elapsed_s": end.elapsed_s,
        "completion_time_s": end.completion_time_s,
        "boxes_delivered": end.boxes_delivered,
        "score": end.score,
        "path_length_m": m.path_length_m,
        "smoothness": m.smoothness,
        "active_ratio": m.active_ratio,
        "hz_wall": m.hz_wall,
        "hz_sim": m.hz_sim,
        "max_gap_s": m.max_gap_s,
        "quality_flags": FLAG_SEPARATOR.join(end.quality_flags),
        "included": int(included),
        "exclusion_reason": reason,
        "ended_wall": time.time(),
        "stage": end.stage,
        "progress": end.progress,
    }


def checked_batch(batch: RowBatch, fixed: Mapping[str, str]) -> RowBatch:
    """A ready batch of frames, with its ids those of the trial it is added to."""
    if batch.layout is not FRAMES:
        raise RecordError(f"a {batch.layout.name} batch cannot be added as frames")
    ids = (fixed["session_id"], fixed["trial_id"])
    for i, row in enumerate(batch.text):
        if row[:2] != ids:
            raise RecordError(f"frames row {i}: session_id, trial_id {row[:2]} are not {ids}")
    return batch


_FRAME_INDEX = FRAMES.of_kind("integer").index("frame_index")


def frame_batch(frames: RowBatch, trial: Running, trial_id: str) -> RowBatch:
    """A batch handed to :meth:`Store.add_frames <workcell.record.store.Store.add_frames>`,
    checked to be the trial's next rows."""
    if not isinstance(frames, RowBatch):
        raise RecordError(
            f"frames of trial {trial_id}: expected a RowBatch of the frames layout, "
            f"got {type(frames).__name__}"
        )
    batch = checked_batch(frames, {"session_id": trial.session_id, "trial_id": trial_id})
    n = len(batch)
    indices = [row[_FRAME_INDEX] for row in batch.integer]
    if indices != list(range(trial.next_index, trial.next_index + n)):
        raise RecordError(
            f"frames of trial {trial_id} must continue at frame_index {trial.next_index} "
            f"in steps of 1; got {indices[:3]}{'...' if n > 3 else ''}"
        )
    return batch

"""Reading a store for an audit: one read-only snapshot, the needed frame columns only.

A closed trial's frames are read from its frame block (:mod:`workcell.record.frame_blocks`:
the 41 columns the metrics use, stored column by column when the trial closed, checked
against the rows by ``workcell verify``) when the block holds as many frames as the trial
row says; otherwise, and for every trial with ``use_blocks=False``, with one SELECT of those
columns per trial, straight into a float matrix (NULL becomes NaN). The store's own
:meth:`Store.frames` reads every column and rebuilds checksummed batches, which an audit
does not need.
"""

from __future__ import annotations

import json
import sqlite3
from collections.abc import Collection, Iterator
from functools import partial
from pathlib import Path
from typing import Literal

import numpy as np

from workcell.audit.rows import SessionRow, TrialRow
from workcell.audit.source import (
    FRAME_COLUMNS_READ,
    MIDPOINT_COLUMNS,
    FloatArray,
    Pauses,
    Switches,
    midpoint_xy,
    pause_of,
)
from workcell.audit.task_stages import (
    HOLDS_SQL,
    SIGNALS_SQL,
    STAGE_COLUMNS,
    StageFrames,
    holds_from_sql,
    stage_frames,
    started_conditions,
)
from workcell.metrics import FrameArrays
from workcell.record.connection import connect
from workcell.record.entries import AnnotationRecord
from workcell.record.frame_blocks import BLOCK_COLUMNS, has_blocks, read_block
from workcell.record.rowio import select
from workcell.record.schema import ANNOTATIONS, SESSIONS, TRIALS, column_list

MMAP_BYTES = 1 << 30
"""Memory-map up to this much of the store file: fewer copies on a large read."""

SESSION_ORDER = "created_wall, session_id"
TRIAL_ORDER = "started_wall, trial_index"


_MIDPOINT_IN_BLOCK = [BLOCK_COLUMNS.index(name) for name in MIDPOINT_COLUMNS]


def _frames_sql(names: tuple[str, ...]) -> str:
    return f"SELECT {column_list(names)} FROM frames WHERE trial_id = ? ORDER BY frame_index"


class StoreSource:
    """An open store, read in one consistent snapshot (a recorder may keep writing)."""

    kind: Literal["store"] = "store"

    def __init__(self, path: Path, *, use_blocks: bool = True) -> None:
        self.path = path
        self._conn = connect(path, writer=False, check=True)
        self._conn.execute(f"PRAGMA mmap_size = {MMAP_BYTES}")
        self._conn.execute("BEGIN")  # the snapshot every read below sees
        self.use_blocks = use_blocks and has_blocks(self._conn)
        """Whether frames are read from frame blocks where they agree with the trial row."""
        self.read_from_blocks = 0
        """Trials whose frames came from their frame block (the others from rows)."""

    def sessions(self) -> list[SessionRow]:
        return [
            SessionRow.parse(
                row, json.loads(row["parameters_json"]), json.loads(row["thresholds_json"])
            )
            for row in select(self._conn, SESSIONS, order=SESSION_ORDER)
        ]

    def trials(self) -> list[TrialRow]:
        return [TrialRow.parse(row) for row in select(self._conn, TRIALS, order=TRIAL_ORDER)]

    def annotations(self) -> list[AnnotationRecord]:
        rows = select(self._conn, ANNOTATIONS, order="at_wall, annotation_id")
        return [AnnotationRecord.from_row(row) for row in rows]

    def frames(self) -> Iterator[tuple[str, FrameArrays]]:
        trials = self._conn.execute(f"SELECT trial_id FROM trials ORDER BY {TRIAL_ORDER}")
        return self.frames_of([trial_id for (trial_id,) in trials.fetchall()])

    def frames_of(self, trial_ids: Collection[str]) -> Iterator[tuple[str, FrameArrays]]:
        """(trial_id, frames) of the given trials, in the order given."""
        sql = _frames_sql(FRAME_COLUMNS_READ)
        n_frames = self._frame_counts()
        for trial_id in trial_ids:
            matrix = self._block(trial_id, n_frames.get(trial_id))
            if matrix is None:
                matrix = self._matrix(sql, trial_id, len(FRAME_COLUMNS_READ))
            yield trial_id, FrameArrays.from_matrix(matrix)

    def midpoints(self, trial_ids: Collection[str]) -> dict[str, FloatArray]:
        sql = _frames_sql(MIDPOINT_COLUMNS)
        n_frames = self._frame_counts()
        out = {}
        for trial_id in trial_ids:
            block = self._block(trial_id, n_frames.get(trial_id), count=False)
            if block is not None:
                out[trial_id] = midpoint_xy(block[:, _MIDPOINT_IN_BLOCK])
            else:
                out[trial_id] = midpoint_xy(self._matrix(sql, trial_id, len(MIDPOINT_COLUMNS)))
        return out

    def stage_frames(self, trial_ids: Collection[str]) -> dict[str, StageFrames]:
        out = {}
        for trial_id in trial_ids:
            try:
                holds = self._conn.execute(HOLDS_SQL, (trial_id,)).fetchall()
            except sqlite3.OperationalError:  # a boxes cell that is not JSON
                rows = self._conn.execute(_frames_sql(STAGE_COLUMNS), (trial_id,))
                out[trial_id] = stage_frames(rows)
                continue
            # a hold is a touch and a grasp: only a trial without one needs the signals
            signals = (1, 1) if holds else self._conn.execute(SIGNALS_SQL, (trial_id,)).fetchone()
            out[trial_id] = holds_from_sql(signals, holds, partial(self._boxes, trial_id))
        return out

    def _boxes(self, trial_id: str, frame_index: int) -> str | None:
        row = self._conn.execute(
            "SELECT boxes FROM frames WHERE trial_id = ? AND frame_index = ?",
            (trial_id, frame_index),
        ).fetchone()
        return row[0] if row is not None and isinstance(row[0], str) else None

    def trial_conditions(self, trial_ids: Collection[str]) -> dict[str, dict[str, object]]:
        sql = "SELECT payload_json FROM events WHERE trial_id = ? AND kind = 'trial_started'"
        out = {}
        for trial_id in trial_ids:
            row = self._conn.execute(sql, (trial_id,)).fetchone()
            if row is not None:
                out[trial_id] = started_conditions(row[0])
        return out

    def trial_pauses(self, trial_ids: Collection[str]) -> dict[str, Pauses]:
        wanted = set(trial_ids)
        sql = "SELECT trial_id, t_sim, payload_json FROM events WHERE kind = 'resumed' ORDER BY seq"
        out: dict[str, list[tuple[float, float]]] = {}
        for trial_id, t_sim, payload in self._conn.execute(sql):
            pause = pause_of(t_sim, payload) if trial_id in wanted else None
            if pause is not None:
                out.setdefault(trial_id, []).append(pause)
        return {trial_id: tuple(pauses) for trial_id, pauses in out.items()}

    def trial_switches(self, trial_ids: Collection[str]) -> dict[str, Switches]:
        wanted = set(trial_ids)
        sql = (
            "SELECT trial_id, kind, t_sim FROM events "
            "WHERE kind IN ('take_over', 'hand_back') ORDER BY seq"
        )
        out: dict[str, list[tuple[str, float]]] = {}
        for trial_id, kind, t_sim in self._conn.execute(sql):
            if trial_id in wanted and t_sim is not None:
                out.setdefault(trial_id, []).append((kind, float(t_sim)))
        return {trial_id: tuple(switches) for trial_id, switches in out.items()}

    def _frame_counts(self) -> dict[str, int | None]:
        """Each trial's n_frames as its row says (None while it runs)."""
        return dict(self._conn.execute("SELECT trial_id, n_frames FROM trials").fetchall())

    def _block(
        self, trial_id: str, n_frames: int | None, *, count: bool = True
    ) -> FloatArray | None:
        if not self.use_blocks or n_frames is None:
            return None
        block = read_block(self._conn, trial_id, n_frames)
        if block is not None and count:
            self.read_from_blocks += 1
        return block

    def close(self) -> None:
        self._conn.close()

    def _matrix(self, sql: str, trial_id: str, width: int) -> FloatArray:
        cursor: sqlite3.Cursor = self._conn.execute(sql, (trial_id,))
        return np.fromiter(cursor, dtype=np.dtype((np.float64, width)))

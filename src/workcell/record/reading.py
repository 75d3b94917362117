"""Reading a store: rows as records, frames as columns. Shared by readers and writers."""

from __future__ import annotations

import sqlite3
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from workcell.record import chain, rowio
from workcell.record.batch import RowBatch
from workcell.record.entries import (
    AnnotationRecord,
    EventRecord,
    SessionRecord,
    StoreCounts,
    TrialRecord,
)
from workcell.record.schema import ANNOTATIONS, EVENTS, FRAMES, SESSIONS, TRIALS


class StoreReading:
    """The read half of a :class:`~workcell.record.store.Store`: it sees what is
    committed (and, in a writer, what it has added but not yet committed)."""

    path: Path
    _conn: sqlite3.Connection

    def sessions(self) -> list[SessionRecord]:
        rows = rowio.select(self._conn, SESSIONS, order="created_wall, session_id")
        return [SessionRecord.from_row(row) for row in rows]

    def trials(self, session_id: str | None = None) -> list[TrialRecord]:
        where, params = _filter(session_id=session_id)
        rows = rowio.select(self._conn, TRIALS, where, params, "started_wall, trial_index")
        return [TrialRecord.from_row(row) for row in rows]

    def events(
        self, trial_id: str | None = None, *, session_id: str | None = None
    ) -> list[EventRecord]:
        """Events of a trial, or of a session (all of its events), or all, by seq."""
        where, params = _filter(trial_id=trial_id, session_id=session_id)
        rows = rowio.select(self._conn, EVENTS, where, params, "session_id, seq")
        return [EventRecord.from_row(row) for row in rows]

    def annotations(self, trial_id: str | None = None) -> list[AnnotationRecord]:
        where, params = _filter(trial_id=trial_id)
        rows = rowio.select(self._conn, ANNOTATIONS, where, params, "at_wall")
        return [AnnotationRecord.from_row(row) for row in rows]

    def frames(self, trial_id: str) -> dict[str, NDArray[Any]]:
        """The trial's frames as columns in ``FRAME_COLUMNS`` order: text as object arrays,
        reals as float64 (NaN for NULL), integers as int64, or as float64 with NaN where
        NULL is legitimate (``buttons_*``)."""
        parts = [
            batch.to_columns()
            for batch, _, _ in rowio.select_grouped(
                self._conn, FRAMES, "trial_id = ?", (trial_id,), "frame_index"
            )
        ]
        if not parts:
            return RowBatch.from_grouped(FRAMES, []).to_columns()
        return {name: np.concatenate([p[name] for p in parts]) for name in FRAMES.names}

    def counts(self) -> StoreCounts:
        def count(table: str) -> int:
            return int(self._conn.execute(f"SELECT count(*) FROM {table}").fetchone()[0])

        return StoreCounts(
            *(count(t) for t in ("sessions", "trials", "events", "frames", "annotations"))
        )

    def chain(self, session_id: str | None = None) -> list[chain.Link]:
        """The hash-chain links of one session (or of all), by session and position."""
        return chain.links(self._conn, session_id)

    def meta(self) -> dict[str, str]:
        """The store's ``meta`` table: schema_version, software_version, store_id, ..."""
        return dict(self._conn.execute("SELECT key, value FROM meta ORDER BY key"))


def _filter(**ids: str | None) -> tuple[str, tuple[str, ...]]:
    given = {name: value for name, value in ids.items() if value is not None}
    return " AND ".join(f"{name} = ?" for name in given), tuple(given.values())

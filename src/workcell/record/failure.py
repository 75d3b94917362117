"""Closing a session after its recording failed (a full disk, an I/O error, a dead writer).

The failed transaction has been rolled back; what was committed before is intact. The
store then closes the session's running trial as ``interrupted`` with the reason the
caller gives (``storage_error``) and an ``interruption`` event naming the error, and the
session as ``interrupted``, with their chain links, in one durable transaction. A trial
whose row went down with the failed transaction (the disk filled as its start was being
written) is written again first, so that every trial the operator was told of is stored. On a full
disk this write needs room the disk no longer has: the writer's headroom file
(:mod:`workcell.record.reserve`) is deleted first to give it that room.
"""

from __future__ import annotations

import contextlib
import sqlite3
import time
from collections.abc import Mapping

from workcell.record import lifecycle, rowio
from workcell.record.batch import RowBatch
from workcell.record.chain import ChainKey
from workcell.record.errors import StoreError
from workcell.record.ids import new_id
from workcell.record.reserve import Reserve
from workcell.record.writes import WriteGuard

ATTEMPTS = 3


def close_after_failure(
    conn: sqlite3.Connection,
    *,
    guard: WriteGuard,
    reserve: Reserve,
    session_id: str,
    reason: str,
    key: ChainKey | None,
    started: Mapping[str, RowBatch] | None = None,
) -> bool:
    """Close the session's running trials as interrupted (``reason``) and the session as
    ``interrupted``; whether it was written. ``started``: the rows of the trials, by id,
    the writer started in the session and has not ended, written again when missing.
    Never raises for storage trouble (the next writer recovers what is left open)."""
    failure = guard.failure
    detail = {"error": str(failure)} if failure else {}
    if failure is None:  # keep what was added; a failing commit rolls back instead
        with contextlib.suppress(StoreError):
            guard.commit()
    else:
        reserve.release()  # the room to write the end in
    for attempt in range(ATTEMPTS):
        try:
            guard.rollback()
            conn.execute("PRAGMA synchronous = FULL")  # the end is durable
            conn.execute("BEGIN IMMEDIATE")
            now = time.time()
            for trial_id, row in (started or {}).items():
                _restore_start(conn, trial_id, row)
            for trial_id in lifecycle.running_trials(conn, session_id):
                lifecycle.interrupt_trial(
                    conn, trial_id, reason, event_id=new_id(), now=now, detail=detail, key=key
                )
            lifecycle.close_session(conn, session_id, "interrupted", now, key)
            conn.execute("COMMIT")
            return True
        except (sqlite3.Error, OSError):
            guard.rollback()
            if attempt == 0:  # free room in the log by moving its pages into the database
                with contextlib.suppress(sqlite3.Error, OSError):
                    conn.execute("PRAGMA wal_checkpoint(TRUNCATE)")
        finally:
            with contextlib.suppress(sqlite3.Error):
                if not conn.in_transaction:
                    conn.execute("PRAGMA synchronous = NORMAL")
    return False


def _restore_start(conn: sqlite3.Connection, trial_id: str, row: RowBatch) -> None:
    """Write a started trial's row again if the rolled-back transaction took it."""
    if conn.execute("SELECT 1 FROM trials WHERE trial_id = ?", (trial_id,)).fetchone() is None:
        rowio.insert(conn, row)

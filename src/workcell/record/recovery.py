"""Crash recovery: what a writer does first when it opens a store a dead process left open.

A recorder killed outright (SIGKILL, power cut of the process, OOM) leaves its trial with
no outcome and its session ``running``. Every frame it committed is in the store; the
uncommitted tail (at most one batch) is gone. Recovery closes such trials as
``interrupted``/``crash_recovered`` with their committed frame count, checksums and chain
links, records why, and closes their sessions as ``recovered``. It runs only under the
writer lock, so it never touches a live recorder's trial.

Its ``recovery`` event says what it found of the session's chain (links and head before
the links it added) and whether it signed them: the writer signs them only when the
store's chain tip is signed with its key (:func:`~workcell.record.chain_tip.writer_check`),
that is, when nothing was cut off or rewritten since the key last wrote. Otherwise they
stay unsigned, and ``verify --key`` names them.

A recording process that knows why its session stopped (its store writer process died
under it) passes that reason: its session's running trial is closed as ``interrupted``
with that reason and the session as ``interrupted``, so that the store says what the
operator was told.
"""

from __future__ import annotations

import contextlib
import math
import sqlite3
import time
from collections.abc import Mapping
from dataclasses import dataclass, field

from workcell.record import lifecycle
from workcell.record.chain import ChainKey
from workcell.record.diagnose import storage_advice
from workcell.record.errors import StorageError
from workcell.record.ids import new_id
from workcell.record.reserve import Reserve

CRASH_RECOVERED = "crash_recovered"


@dataclass(frozen=True)
class KnownEnd:
    """Why a session stopped, as its recording process knows it."""

    reason: str
    detail: Mapping[str, object] = field(default_factory=dict)


def recover(
    conn: sqlite3.Connection,
    key: ChainKey | None = None,
    known: Mapping[str, KnownEnd] | None = None,
) -> tuple[str, ...]:
    """Close every orphan trial and session (in one transaction); returns the trial ids.
    ``known``: session id → why it stopped, for sessions whose recorder said so."""
    known = known or {}
    now = time.time()
    orphans = lifecycle.running_trials(conn)
    sessions = [
        r[0]
        for r in conn.execute(
            "SELECT session_id FROM sessions WHERE status = 'running' ORDER BY created_wall"
        )
    ]
    if not orphans and not sessions:
        return ()
    conn.execute("BEGIN IMMEDIATE")
    try:
        found = {session_id: _found(conn, session_id) for session_id in sessions}
        for trial_id in orphans:
            (session_id,) = conn.execute(
                "SELECT session_id FROM trials WHERE trial_id = ?", (trial_id,)
            ).fetchone()
            end = known.get(session_id)
            lifecycle.interrupt_trial(
                conn,
                trial_id,
                CRASH_RECOVERED if end is None else end.reason,
                event_id=new_id(),
                now=now,
                detail={"recovered_wall": now} if end is None else dict(end.detail),
                key=key,
            )
        for session_id in sessions:
            if session_id in known:
                lifecycle.close_session(conn, session_id, "interrupted", now, key)
            else:
                _close_session(conn, session_id, orphans, now, key, found=found[session_id])
        conn.execute("COMMIT")
    except BaseException:
        with contextlib.suppress(sqlite3.Error):  # a full disk may have rolled it back
            if conn.in_transaction:
                conn.execute("ROLLBACK")
        raise
    return tuple(orphans)


def _close_session(
    conn: sqlite3.Connection,
    session_id: str,
    orphans: list[str],
    now: float,
    key: ChainKey | None,
    *,
    found: dict[str, object],
) -> None:
    recovered = [
        r[0]
        for r in conn.execute(
            "SELECT trial_id FROM trials WHERE session_id = ? ORDER BY trial_index",
            (session_id,),
        )
        if r[0] in orphans
    ]
    (last_wall,) = conn.execute(
        "SELECT max(t) FROM (SELECT created_wall AS t FROM sessions WHERE session_id = ?1 "
        "UNION ALL SELECT ended_wall FROM trials WHERE session_id = ?1 "
        "UNION ALL SELECT t_wall FROM events WHERE session_id = ?1)",
        (session_id,),
    ).fetchone()
    lifecycle.insert_event(
        conn,
        event_id=new_id(),
        session_id=session_id,
        trial_id=None,
        seq=lifecycle.next_seq(conn, session_id),
        kind=lifecycle.RECOVERY_EVENT,
        payload={
            "reason": CRASH_RECOVERED,
            "trials": recovered,
            "recovered_wall": now,
            "found": found,
            "signed": key is not None,
        },
        t_sim=None,
        t_wall=max(now, last_wall if last_wall is not None else -math.inf),
    )
    lifecycle.close_session(conn, session_id, "recovered", last_wall, key)


def _found(conn: sqlite3.Connection, session_id: str) -> dict[str, object]:
    """What recovery found of the session's chain: its links and head before it closed it."""
    links = conn.execute(
        "SELECT position, head FROM chain WHERE session_id = ? ORDER BY position DESC LIMIT 1",
        (session_id,),
    ).fetchone()
    return {"links": 0, "head": ""} if links is None else {"links": links[0] + 1, "head": links[1]}


def recover_with_headroom(
    conn: sqlite3.Connection,
    reserve: Reserve,
    *,
    key: ChainKey | None,
    known: Mapping[str, KnownEnd],
) -> tuple[str, ...]:
    """:func:`recover`; on a full disk, into the room of the headroom file. Raises
    :class:`StorageError` naming the disk when even that fails."""
    for attempt in range(2):
        try:
            return recover(conn, key, known)
        except (sqlite3.Error, OSError) as error:
            if attempt == 0 and reserve.release():
                continue
            cause = str(error).strip() or type(error).__name__
            raise StorageError(
                f"store {reserve.store}: crash recovery could not write ({cause}) — "
                f"{storage_advice(reserve.store, cause)}; the store is unchanged"
            ) from None
    raise AssertionError("unreachable")

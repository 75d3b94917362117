"""Crash recovery: what a writer does first when it opens a store a dead process left open.

A recorder killed outright (SIGKILL, power cut of the process, OOM) leaves its trial with
no outcome and its session ``running``. Every frame it committed is in the store; the
uncommitted tail (at most one batch) is gone. Recovery closes such trials as
``interrupted``/``crash_recovered`` with their committed frame count and checksums, records
why, and closes their sessions as ``recovered``. It runs only under the writer lock, so it
never touches a live recorder's trial.
"""

from __future__ import annotations

import math
import sqlite3
import time

from workcell.record import lifecycle
from workcell.record.ids import new_id

CRASH_RECOVERED = "crash_recovered"


def recover(conn: sqlite3.Connection) -> tuple[str, ...]:
    """Close every orphan trial and session (in one transaction); returns the trial ids."""
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
        for trial_id in orphans:
            lifecycle.interrupt_trial(
                conn,
                trial_id,
                CRASH_RECOVERED,
                event_id=new_id(),
                now=now,
                detail={"recovered_wall": now},
            )
        for session_id in sessions:
            _close_session(conn, session_id, orphans, now)
        conn.execute("COMMIT")
    except BaseException:
        conn.execute("ROLLBACK")
        raise
    return tuple(orphans)


def _close_session(
    conn: sqlite3.Connection, session_id: str, orphans: list[str], now: float
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
        payload={"reason": CRASH_RECOVERED, "trials": recovered, "recovered_wall": now},
        t_sim=None,
        t_wall=max(now, last_wall if last_wall is not None else -math.inf),
    )
    lifecycle.close_session(conn, session_id, "recovered", last_wall)

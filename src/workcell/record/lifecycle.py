"""Closing trials and sessions, shared by the recorder's path, storage-error handling and
crash recovery, each with its hash-chain link (:mod:`workcell.record.chain`). Every
function runs inside the caller's write transaction."""

from __future__ import annotations

import math
import sqlite3
from collections.abc import Mapping

from workcell.record import chain, rowio
from workcell.record.chain import ChainKey
from workcell.record.checksum import aggregate_checksum
from workcell.record.entries import to_json
from workcell.record.inclusion import incomplete_reason
from workcell.record.schema import EVENTS, SESSIONS, TRIALS

INTERRUPTION_EVENT = "interruption"
"""Event the store records when it closes a trial as interrupted itself."""
RECOVERY_EVENT = "recovery"
"""Session-level event crash recovery records when it closes a session."""


def next_seq(conn: sqlite3.Connection, session_id: str) -> int:
    row = conn.execute(
        "SELECT coalesce(max(seq) + 1, 0) FROM events WHERE session_id = ?", (session_id,)
    ).fetchone()
    return int(row[0])


def insert_event(
    conn: sqlite3.Connection,
    *,
    event_id: str,
    session_id: str,
    trial_id: str | None,
    seq: int,
    kind: str,
    payload: Mapping[str, object],
    t_sim: float | None,
    t_wall: float,
) -> None:
    rowio.insert_one(
        conn,
        EVENTS,
        {
            "event_id": event_id,
            "session_id": session_id,
            "trial_id": trial_id,
            "seq": seq,
            "t_sim": t_sim,
            "t_wall": t_wall,
            "kind": kind,
            "payload_json": to_json(dict(payload), f"event {kind} payload"),
        },
    )


def trial_content_checksum(conn: sqlite3.Connection, trial_id: str) -> str:
    """Aggregate over the trial's frame checksums (by frame_index) and event checksums
    (by seq)."""
    frames = [
        r[0]
        for r in conn.execute(
            "SELECT checksum FROM frames WHERE trial_id = ? ORDER BY frame_index", (trial_id,)
        )
    ]
    events = [
        r[0]
        for r in conn.execute(
            "SELECT checksum FROM events WHERE trial_id = ? ORDER BY seq", (trial_id,)
        )
    ]
    return aggregate_checksum("trial-content", (frames, events))


def session_content_checksum(conn: sqlite3.Connection, session_id: str) -> str:
    """Aggregate over the session's trial checksums (by trial_index) and its session-level
    event checksums (by seq)."""
    trials = [
        r[0]
        for r in conn.execute(
            "SELECT checksum FROM trials WHERE session_id = ? ORDER BY trial_index",
            (session_id,),
        )
    ]
    events = [
        r[0]
        for r in conn.execute(
            "SELECT checksum FROM events WHERE session_id = ? AND trial_id IS NULL ORDER BY seq",
            (session_id,),
        )
    ]
    return aggregate_checksum("session-content", (trials, events))


def close_trial(conn: sqlite3.Connection, trial_id: str, changes: Mapping[str, object]) -> None:
    """Write the trial's end columns, its frame count and its aggregate checksum."""
    (n_frames,) = conn.execute(
        "SELECT count(*) FROM frames WHERE trial_id = ?", (trial_id,)
    ).fetchone()
    rowio.update(
        conn,
        TRIALS,
        {"trial_id": trial_id},
        {
            **changes,
            "n_frames": n_frames,
            "content_checksum": trial_content_checksum(conn, trial_id),
        },
    )


def interrupt_trial(
    conn: sqlite3.Connection,
    trial_id: str,
    reason: str,
    *,
    event_id: str,
    now: float,
    detail: Mapping[str, object],
    key: ChainKey | None,
) -> None:
    """Close a trial as interrupted by the store itself (crash recovery, storage error):
    an ``interruption`` event, elapsed = last sim time seen, ended = last wall time seen,
    its stage and progress its last frame's (NULL without frames or before schema version
    5); then its chain link."""
    session_id, started_wall = conn.execute(
        "SELECT session_id, started_wall FROM trials WHERE trial_id = ?", (trial_id,)
    ).fetchone()
    last_sim, last_wall = _last_times(conn, trial_id)
    last_frame = conn.execute(
        "SELECT stage, progress FROM frames WHERE trial_id = ? ORDER BY frame_index DESC LIMIT 1",
        (trial_id,),
    ).fetchone()
    stage, progress = last_frame if last_frame is not None else (None, None)
    insert_event(
        conn,
        event_id=event_id,
        session_id=session_id,
        trial_id=trial_id,
        seq=next_seq(conn, session_id),
        kind=INTERRUPTION_EVENT,
        payload={"reason": reason, **detail},
        t_sim=last_sim,
        t_wall=max(now, last_wall),
    )
    close_trial(
        conn,
        trial_id,
        {
            "outcome": "interrupted",
            "interruption_reason": reason,
            "included": 0,  # incomplete: never included (workcell.record.inclusion)
            "exclusion_reason": incomplete_reason("interrupted", reason),
            "elapsed_s": last_sim,
            "ended_wall": max(started_wall, last_wall),
            "stage": stage,
            "progress": progress,
        },
    )
    chain.link_trial(conn, trial_id, key)


def close_session(
    conn: sqlite3.Connection,
    session_id: str,
    status: str,
    ended_wall: float,
    key: ChainKey | None,
) -> None:
    """Write the session's status, end time and aggregate checksum, then its last chain
    link."""
    rowio.update(
        conn,
        SESSIONS,
        {"session_id": session_id},
        {
            "status": status,
            "ended_wall": ended_wall,
            "content_checksum": session_content_checksum(conn, session_id),
        },
    )
    chain.link_end(conn, session_id, key)


def running_trials(conn: sqlite3.Connection, session_id: str | None = None) -> list[str]:
    sql = "SELECT trial_id FROM trials WHERE outcome IS NULL"
    params: tuple[str, ...] = ()
    if session_id is not None:
        sql += " AND session_id = ?"
        params = (session_id,)
    return [r[0] for r in conn.execute(sql + " ORDER BY started_wall", params)]


def _last_times(conn: sqlite3.Connection, trial_id: str) -> tuple[float, float]:
    """The latest sim and wall times among the trial's frames and events (0 / -inf if
    none), so an event added after them keeps both clocks monotonic."""
    frame_sim, frame_wall = conn.execute(
        "SELECT max(t_sim), max(t_wall) FROM frames WHERE trial_id = ?", (trial_id,)
    ).fetchone()
    event_sim, event_wall = conn.execute(
        "SELECT max(t_sim), max(t_wall) FROM events WHERE trial_id = ?", (trial_id,)
    ).fetchone()
    sims = [t for t in (frame_sim, event_sim) if t is not None]
    walls = [t for t in (frame_wall, event_wall) if t is not None]
    return (max(sims) if sims else 0.0, max(walls) if walls else -math.inf)

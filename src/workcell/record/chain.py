"""The hash chain: each session's record, link by link, committed to by one hash.

Every row already carries a sha256 of its content, and every closed trial and session an
aggregate of its children's. Those show that a row changed, unless whoever changed it also
recomputed them with this project's own functions. The chain adds an order and an anchor:

- **start**: when a session is created, link 0 commits to its row as created (status
  ``running``) and to ``previous``, the newest head in the store at that moment (another
  session's, or the store's own root in a new store: :mod:`workcell.record.chain_tip`),
  so sessions are chained to one another and to their store;
- **trial**: when a trial closes, a link commits to the head before it, the trial's row
  (whose ``content_checksum`` covers every frame and event of the trial), its frame
  block, and the session-level events recorded since the previous link;
- **end**: when the session closes, a last link commits to the head before it, the
  session's closed row (whose ``content_checksum`` covers every trial and session event)
  and the remaining session-level events.

``head = sha256(previous, kind, session, subject, position, events_through, digest)``,
so the last head depends on every row of the session and on their order. With a key
(``--key FILE``) every head is also signed, ``HMAC-SHA256(key, head)``: a chain
recomputed without the key no longer verifies. The heads go into export manifests, so a
copy of the manifest kept elsewhere anchors the session as it was exported.

Every link also moves the store's chain tip (:mod:`workcell.record.chain_tip`), so that
deleting the newest links shows. Links are written by whoever closes the trial or
session, in the same transaction: the
store writer process while recording (never the simulation's thread), the store itself
after a storage error, crash recovery for what a dead writer left open.
"""

from __future__ import annotations

import hashlib
import sqlite3
import time
from dataclasses import dataclass

from workcell.record import chain_tip, rowio
from workcell.record.batch import RowBatch
from workcell.record.chain_key import ChainKey as ChainKey  # noqa: PLC0414 (re-exported)
from workcell.record.checksum import aggregate_checksum
from workcell.record.schema import SESSIONS

START, TRIAL, END = "start", "trial", "end"
KINDS = (START, TRIAL, END)


@dataclass(frozen=True)
class Link:
    """One row of the ``chain`` table."""

    session_id: str
    position: int
    kind: str
    subject_id: str
    events_through: int
    previous: str
    digest: str
    head: str
    key_id: str | None
    signature: str | None
    created_wall: float

    def expected_head(self) -> str:
        return link_head(
            previous=self.previous,
            kind=self.kind,
            session_id=self.session_id,
            subject_id=self.subject_id,
            position=self.position,
            events_through=self.events_through,
            digest=self.digest,
        )


LINK_COLUMNS = (
    "session_id, position, kind, subject_id, events_through, previous, digest, head, "
    "key_id, signature, created_wall"
)


def link_head(
    *,
    previous: str,
    kind: str,
    session_id: str,
    subject_id: str,
    position: int,
    events_through: int,
    digest: str,
) -> str:
    fields = (previous, kind, session_id, subject_id, str(position), str(events_through), digest)
    return hashlib.sha256(("workcell/chain/v1\0" + "\0".join(fields)).encode()).hexdigest()


CREATED_SESSION = {"status": "running", "ended_wall": None, "content_checksum": None}
"""The columns of a session row that change when it closes, as they are at its start."""


def created_session_checksum(row: dict[str, object]) -> str:
    """The checksum the session row ``row`` had when it was created."""
    return RowBatch.from_mappings(SESSIONS, [row | CREATED_SESSION]).checksums()[0]


def start_digest(created_row_checksum: str) -> str:
    return aggregate_checksum("chain-start", ([created_row_checksum],))


def trial_digest(trial_checksum: str, block_checksum: str | None, events: list[str]) -> str:
    return aggregate_checksum("chain-trial", ([trial_checksum], [block_checksum or ""], events))


def end_digest(session_checksum: str, events: list[str]) -> str:
    return aggregate_checksum("chain-end", ([session_checksum], events))


def links(conn: sqlite3.Connection, session_id: str | None = None) -> list[Link]:
    """The links of one session (or of all), by session and position."""
    sql = f"SELECT {LINK_COLUMNS} FROM chain"
    params: tuple[str, ...] = ()
    if session_id is not None:
        sql += " WHERE session_id = ?"
        params = (session_id,)
    return [Link(*row) for row in conn.execute(sql + " ORDER BY session_id, position", params)]


def store_tip(conn: sqlite3.Connection) -> str:
    """The newest head in the store ('' when it has none)."""
    row = conn.execute("SELECT head FROM chain ORDER BY rowid DESC LIMIT 1").fetchone()
    return "" if row is None else str(row[0])


def session_events(
    conn: sqlite3.Connection, session_id: str, after: int, through: int
) -> list[str]:
    """Checksums of the session-level events with ``after < seq <= through``, by seq."""
    rows = conn.execute(
        "SELECT checksum FROM events WHERE session_id = ? AND trial_id IS NULL "
        "AND seq > ? AND seq <= ? ORDER BY seq",
        (session_id, after, through),
    )
    return [r[0] for r in rows]


def _append(
    conn: sqlite3.Connection,
    *,
    session_id: str,
    kind: str,
    subject_id: str,
    digest: str,
    events_through: int,
    key: ChainKey | None,
    previous: str | None = None,
) -> None:
    last = conn.execute(
        "SELECT position, head FROM chain WHERE session_id = ? ORDER BY position DESC LIMIT 1",
        (session_id,),
    ).fetchone()
    position = 0 if last is None else last[0] + 1
    if previous is None:
        previous = "" if last is None else last[1]
    head = link_head(
        previous=previous,
        kind=kind,
        session_id=session_id,
        subject_id=subject_id,
        position=position,
        events_through=events_through,
        digest=digest,
    )
    conn.execute(
        f"INSERT INTO chain ({LINK_COLUMNS}) VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)",
        (
            session_id,
            position,
            kind,
            subject_id,
            events_through,
            previous,
            digest,
            head,
            None if key is None else key.key_id,
            None if key is None else key.sign(head),
            time.time(),
        ),
    )
    chain_tip.write_tip(conn, key)


def _events_so_far(conn: sqlite3.Connection, session_id: str) -> tuple[int, int]:
    """(events_through of the session's last link, the session's last event seq)."""
    last = conn.execute(
        "SELECT events_through FROM chain WHERE session_id = ? ORDER BY position DESC LIMIT 1",
        (session_id,),
    ).fetchone()
    (seq,) = conn.execute(
        "SELECT coalesce(max(seq), -1) FROM events WHERE session_id = ?", (session_id,)
    ).fetchone()
    return (-1 if last is None else int(last[0])), int(seq)


def link_start(
    conn: sqlite3.Connection, session_id: str, created_row_checksum: str, key: ChainKey | None
) -> None:
    """Link 0 of a new session (in the transaction that inserted its row)."""
    digest = start_digest(created_row_checksum)
    _append(
        conn,
        session_id=session_id,
        kind=START,
        subject_id=session_id,
        digest=digest,
        events_through=-1,
        key=key,
        previous=store_tip(conn) or chain_tip.own_root(conn),
    )


def link_trial(conn: sqlite3.Connection, trial_id: str, key: ChainKey | None) -> None:
    """The link of a trial just closed (after its row and frame block are written)."""
    session_id, trial_checksum = conn.execute(
        "SELECT session_id, checksum FROM trials WHERE trial_id = ?", (trial_id,)
    ).fetchone()
    block = conn.execute(
        "SELECT checksum FROM frame_blocks WHERE trial_id = ?", (trial_id,)
    ).fetchone()
    after, through = _events_so_far(conn, session_id)
    events = session_events(conn, session_id, after, through)
    digest = trial_digest(trial_checksum, None if block is None else block[0], events)
    _append(
        conn,
        session_id=session_id,
        kind=TRIAL,
        subject_id=trial_id,
        digest=digest,
        events_through=through,
        key=key,
    )


def link_end(conn: sqlite3.Connection, session_id: str, key: ChainKey | None) -> None:
    """The last link of a session just closed (after its row is written)."""
    (session_checksum,) = conn.execute(
        "SELECT checksum FROM sessions WHERE session_id = ?", (session_id,)
    ).fetchone()
    after, through = _events_so_far(conn, session_id)
    events = session_events(conn, session_id, after, through)
    _append(
        conn,
        session_id=session_id,
        kind=END,
        subject_id=session_id,
        digest=end_digest(session_checksum, events),
        events_through=through,
        key=key,
    )


def chain_existing(conn: sqlite3.Connection, key: ChainKey | None) -> None:
    """Links for every session of a store that has none yet, from its rows as they are
    now (what migration does for a store of schema version 1)."""
    chained = {r[0] for r in conn.execute("SELECT DISTINCT session_id FROM chain")}
    sessions = rowio.select(conn, SESSIONS, order="created_wall, session_id")
    for row in sessions:
        session_id = row["session_id"]
        if session_id in chained:
            continue
        link_start(conn, session_id, created_session_checksum(row), key)
        closed = conn.execute(
            "SELECT trial_id FROM trials WHERE session_id = ? AND outcome IS NOT NULL "
            "ORDER BY trial_index",
            (session_id,),
        )
        for (trial_id,) in closed.fetchall():
            link_trial(conn, trial_id, key)
        if row["status"] != "running":
            link_end(conn, session_id, key)

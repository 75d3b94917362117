"""What a careful forger does after editing a store with SQL: recompute every checksum with
the project's own functions, and (optionally) rebuild the hash chains, so that nothing
but the chain, a key or a manifest kept elsewhere can tell."""

from __future__ import annotations

import contextlib
import sqlite3
from collections.abc import Iterator
from pathlib import Path

import numpy as np

from workcell.record import chain, chain_tip, lifecycle, rowio
from workcell.record.chain import ChainKey
from workcell.record.frame_blocks import BLOCK_REALS, write_block
from workcell.record.layout import CHECKSUM
from workcell.record.schema import ANNOTATIONS, EVENTS, FRAMES, SESSIONS, TRIALS, quote


@contextlib.contextmanager
def editing(path: Path) -> Iterator[sqlite3.Connection]:
    """A plain SQLite connection to the store (foreign keys off, as a forger would)."""
    conn = sqlite3.connect(path, isolation_level=None)
    conn.execute("BEGIN")
    try:
        yield conn
        conn.execute("COMMIT")
    finally:
        conn.close()


def _rechecksum(conn: sqlite3.Connection, layout_name: str) -> None:
    layout = {t.name: t for t in (SESSIONS, TRIALS, EVENTS, FRAMES, ANNOTATIONS)}[layout_name]
    for batch, _, found in rowio.select_grouped(conn, layout):
        for key, checksum in zip(found, batch.checksums(), strict=True):
            values = key if isinstance(key, tuple) else (key,)
            where = " AND ".join(f"{quote(k)} = ?" for k in layout.key)
            conn.execute(
                f"UPDATE {quote(layout.name)} SET {CHECKSUM} = ? WHERE {where}",
                (checksum, *values),
            )


def recompute_checksums(conn: sqlite3.Connection) -> None:
    """Every row checksum, frame block and aggregate made consistent with the rows again."""
    for name in ("frames", "events", "annotations"):
        _rechecksum(conn, name)
    conn.execute("DELETE FROM frame_blocks")
    for (trial_id,) in conn.execute(
        "SELECT trial_id FROM trials WHERE outcome IS NOT NULL"
    ).fetchall():
        parts = [
            batch.real[:, BLOCK_REALS]
            for batch, _, _ in rowio.select_grouped(
                conn, FRAMES, "trial_id = ?", (trial_id,), "frame_index"
            )
        ]
        matrix = np.concatenate(parts) if parts else np.zeros((0, len(BLOCK_REALS)))
        write_block(conn, trial_id, matrix)
        conn.execute(
            "UPDATE trials SET content_checksum = ? WHERE trial_id = ?",
            (lifecycle.trial_content_checksum(conn, trial_id), trial_id),
        )
    _rechecksum(conn, "trials")
    for (session_id,) in conn.execute(
        "SELECT session_id FROM sessions WHERE status != 'running'"
    ).fetchall():
        conn.execute(
            "UPDATE sessions SET content_checksum = ? WHERE session_id = ?",
            (lifecycle.session_content_checksum(conn, session_id), session_id),
        )
    _rechecksum(conn, "sessions")


def rechain(conn: sqlite3.Connection, key: ChainKey | None = None) -> None:
    """Every link recomputed from the rows as they are now, in the order and with the
    event ranges it had, so that sessions that did not change keep their heads; then the
    store's chain tip."""
    renamed: dict[str, str] = {}
    through: dict[str, int] = {}
    rows = conn.execute(f"SELECT rowid, {chain.LINK_COLUMNS} FROM chain ORDER BY rowid").fetchall()
    for rowid, *fields in rows:
        link = chain.Link(*fields)
        after = through.get(link.session_id, -1)
        events = chain.session_events(conn, link.session_id, after, link.events_through)
        through[link.session_id] = max(after, link.events_through)
        if link.kind == chain.START:
            (session,) = rowio.select(conn, SESSIONS, "session_id = ?", (link.session_id,))
            digest = chain.start_digest(chain.created_session_checksum(session))
        elif link.kind == chain.TRIAL:
            (trial_sum,) = conn.execute(
                "SELECT checksum FROM trials WHERE trial_id = ?", (link.subject_id,)
            ).fetchone()
            block = conn.execute(
                "SELECT checksum FROM frame_blocks WHERE trial_id = ?", (link.subject_id,)
            ).fetchone()
            digest = chain.trial_digest(trial_sum, None if block is None else block[0], events)
        else:
            (session_sum,) = conn.execute(
                "SELECT checksum FROM sessions WHERE session_id = ?", (link.session_id,)
            ).fetchone()
            digest = chain.end_digest(session_sum, events)
        previous = renamed.get(link.previous, link.previous)
        head = chain.link_head(
            previous=previous,
            kind=link.kind,
            session_id=link.session_id,
            subject_id=link.subject_id,
            position=link.position,
            events_through=link.events_through,
            digest=digest,
        )
        renamed[link.head] = head
        conn.execute(
            "UPDATE chain SET previous = ?, digest = ?, head = ?, key_id = ?, signature = ? "
            "WHERE rowid = ?",
            (
                previous,
                digest,
                head,
                None if key is None else key.key_id,
                None if key is None else key.sign(head),
                rowid,
            ),
        )
    chain_tip.write_tip(conn, key)

"""Migrating a store written by an older schema version, when a writer opens it.

Version 1 → 2 adds the hash chain (:mod:`workcell.record.chain`): the ``chain`` table, and
for every session already in the store its links, computed from its rows as they are at
the moment of migration (unsigned). Every row is kept as it is. Those chains prove only
that nothing changed *after* the migration; ``meta`` records when it happened
(``migrated_wall``) so that ``workcell verify`` can say which sessions it concerns. It all
runs in one transaction: a failed migration leaves the store as it was.

Version 2 → 3 appends the frames' filtered device poses
(:data:`~workcell.record.columns.FILTERED_POSE_COLUMNS`), NULL in every frame already
recorded. Row checksums leave appended columns out where they are NULL, so every checksum
and chain link stays valid, and ``migrated_wall`` keeps meaning when chains were computed.
"""

from __future__ import annotations

import contextlib
import sqlite3
import time

from workcell import __version__
from workcell.record import chain
from workcell.record.schema import CHAIN_SQL, FRAMES, SCHEMA_VERSION, quote


def _v1_to_v2(conn: sqlite3.Connection) -> None:
    conn.execute(CHAIN_SQL)
    chain.chain_existing(conn, None)


def _v2_to_v3(conn: sqlite3.Connection) -> None:
    for name in FRAMES.appended:
        conn.execute(f"ALTER TABLE {quote(FRAMES.name)} ADD COLUMN {quote(name)} REAL")


MIGRATIONS = {1: _v1_to_v2, 2: _v2_to_v3}
"""Version → the step that takes a store of that version to the next."""
MIGRATION_NOTES = {
    1: "from before hash chains and filtered poses",
    2: "from before the frames' filtered poses",
}
"""Version → what a store of that version lacks, for the message that asks to migrate it."""
CHAINED_BY = 1
"""Migrating from this version (or older) computes the chains of the sessions in the store."""


def migrate(conn: sqlite3.Connection, version: int) -> None:
    """Take the store from ``version`` to :data:`SCHEMA_VERSION`, in one transaction."""
    conn.execute("BEGIN IMMEDIATE")
    try:
        meta = [("schema_version", str(SCHEMA_VERSION)), ("migrated_by", __version__)]
        if version <= CHAINED_BY:
            meta.append(("migrated_wall", repr(time.time())))
        while version < SCHEMA_VERSION:
            MIGRATIONS[version](conn)
            version += 1
        conn.executemany("INSERT OR REPLACE INTO meta (key, value) VALUES (?, ?)", meta)
        conn.execute(f"PRAGMA user_version = {SCHEMA_VERSION}")
        conn.execute("COMMIT")
    except BaseException:
        with contextlib.suppress(sqlite3.Error):
            if conn.in_transaction:
                conn.execute("ROLLBACK")
        raise

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

Version 3 → 4 adds the store's chain roots and tip (:mod:`workcell.record.chain_tip`):
``chain_roots`` with the store's own root and, when its first chains started from an
empty head, that legacy root; then the tip, signed with the writer's key. A store whose
links are signed is migrated only with its key (else its tip could not be signed, and
every keyed writer after would refuse it). The tip vouches for the store as it was
migrated: links deleted before that do not show.

Version 4 → 5 appends the task-neutral columns: the trials' task, world, stage, progress
and goal (:data:`~workcell.record.columns.TRIAL_TASK_COLUMNS`) and the frames' stage and
progress (:data:`~workcell.record.columns.FRAME_TASK_COLUMNS`), NULL in every row already
recorded. As in version 3, a row checksum counts a version's appended columns only where
the row holds one of them, so every checksum and chain link stays valid.

Version 5 → 6 appends who drove: the trials' ``driver``
(:data:`~workcell.record.columns.TRIAL_DRIVER_COLUMNS`) and the frames' ``intervention``
(:data:`~workcell.record.columns.FRAME_INTERVENTION_COLUMNS`), NULL in every row already
recorded, the same way.
"""

from __future__ import annotations

import contextlib
import sqlite3
import time

from workcell import __version__
from workcell.record import chain, chain_tip
from workcell.record.chain_key import ChainKey
from workcell.record.errors import StoreError
from workcell.record.ids import new_id
from workcell.record.layout import TableLayout
from workcell.record.schema import (
    CHAIN_ROOTS_SQL,
    CHAIN_SQL,
    FRAMES,
    SCHEMA_VERSION,
    TRIALS,
    quote,
)


def _v1_to_v2(conn: sqlite3.Connection) -> None:
    conn.execute(CHAIN_SQL)  # the links follow in the last step, from the store's root


def _append(conn: sqlite3.Connection, layout: TableLayout, version: int) -> None:
    """Add the columns schema ``version`` appended to ``layout``'s table (NULL in every row)."""
    for group in layout.added:
        if group.version == version:
            for name in group.names:
                kind = layout.column(name).kind.upper()
                conn.execute(f"ALTER TABLE {quote(layout.name)} ADD COLUMN {quote(name)} {kind}")


def _v2_to_v3(conn: sqlite3.Connection) -> None:
    _append(conn, FRAMES, 3)


def _v3_to_v4(conn: sqlite3.Connection) -> None:
    conn.execute(CHAIN_ROOTS_SQL)
    conn.execute("INSERT OR IGNORE INTO meta (key, value) VALUES ('store_id', ?)", (new_id(),))
    own = chain_tip.store_id(conn)
    chain_tip.declare_root(conn, chain_tip.store_root(own), own, chain_tip.CREATED)
    legacy = conn.execute(
        "SELECT 1 FROM chain WHERE position = 0 AND previous = ?", (chain_tip.LEGACY_ROOT,)
    ).fetchone()
    if legacy:
        chain_tip.declare_root(conn, chain_tip.LEGACY_ROOT, own, chain_tip.MIGRATED)


def _v4_to_v5(conn: sqlite3.Connection) -> None:
    _append(conn, TRIALS, 5)
    _append(conn, FRAMES, 5)


def _v5_to_v6(conn: sqlite3.Connection) -> None:
    _append(conn, TRIALS, 6)
    _append(conn, FRAMES, 6)


MIGRATIONS = {1: _v1_to_v2, 2: _v2_to_v3, 3: _v3_to_v4, 4: _v4_to_v5, 5: _v5_to_v6}
"""Version → the step that takes a store of that version to the next."""
MIGRATION_NOTES = {
    1: "from before hash chains, filtered poses, chain tips, task and driver columns",
    2: "from before the frames' filtered poses, chain tips, task and driver columns",
    3: "from before chain tips, store roots, task and driver columns",
    4: "from before the trials' and frames' task and driver columns",
    5: "from before the trials' driver and the frames' intervention columns",
}
"""Version → what a store of that version lacks, for the message that asks to migrate it."""
CHAINED_BY = 1
"""Migrating from this version (or older) computes the chains of the sessions in the store."""


def migrate(
    conn: sqlite3.Connection, version: int, key: ChainKey | None = None, path: str = "PATH"
) -> None:
    """Take the store (at ``path``) from ``version`` to :data:`SCHEMA_VERSION`, in one
    transaction; the chain tip is signed with ``key`` (a store whose links are signed
    needs it)."""
    if key is None and version >= 2:
        signed = conn.execute(
            "SELECT key_id FROM chain WHERE key_id IS NOT NULL LIMIT 1"
        ).fetchone()
        if signed:
            raise StoreError(
                f"store {path} has schema version {version} and its chain is signed with key "
                f"{signed[0]}: migrate it with that key ('workcell verify --recover --store "
                f"{path} --key FILE'), which signs its chain tip; nothing was changed"
            )
    conn.execute("BEGIN IMMEDIATE")
    try:
        meta = [("schema_version", str(SCHEMA_VERSION)), ("migrated_by", __version__)]
        chained_by_migration = version <= CHAINED_BY
        if chained_by_migration:
            meta.append(("migrated_wall", repr(time.time())))
        while version < SCHEMA_VERSION:
            MIGRATIONS[version](conn)
            version += 1
        if chained_by_migration:
            chain.chain_existing(conn, None)
        chain_tip.write_tip(conn, key)
        conn.executemany("INSERT OR REPLACE INTO meta (key, value) VALUES (?, ?)", meta)
        conn.execute(f"PRAGMA user_version = {SCHEMA_VERSION}")
        conn.execute("COMMIT")
    except BaseException:
        with contextlib.suppress(sqlite3.Error):
            if conn.in_transaction:
                conn.execute("ROLLBACK")
        raise

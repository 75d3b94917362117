"""Combine store shards (one per worker) into one store, and verify the result.

Ids are unique across stores, so rows are copied as they are, hash-chain links included
(their heads and signatures stay valid), the shard's chain roots become roots of the
output and the output's chain tip (:mod:`workcell.record.chain_tip`) moves to the last
link copied, signed with the key given (a signed shard is merged only with a key); each
shard's camera videos join the output's media
folder (:mod:`workcell.record.media_paths`). Shards a dead worker left
open are recovered first, like any crashed store. Shards whose sessions disagree on what a
frame means (joint order, metrics version) or whose schema differs are refused.
"""

from __future__ import annotations

import contextlib
import sqlite3
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Literal

from workcell.record import chain_tip
from workcell.record.chain import ChainKey
from workcell.record.errors import StoreError
from workcell.record.frame_blocks import has_blocks
from workcell.record.media_paths import copy_media, media_dir_for
from workcell.record.schema import SCHEMA_VERSION
from workcell.record.store import Store
from workcell.record.verify import verify_store

TABLE_ORDER = ("sessions", "trials", "events", "frames", "annotations")
"""Parents before children, so foreign keys hold at every step."""


class MergeError(StoreError):
    """Shards cannot be combined; the message names the shard and the reason."""


@dataclass(frozen=True)
class MergeReport:
    shards: int
    sessions: int
    trials: int
    frames: int
    recovered_trials: int
    media_files: int = 0
    """Camera videos copied (or linked) into the output's media folder."""


def _compatibility(path: Path, key: ChainKey | None) -> tuple[int, set[tuple[str, str]], int]:
    """(schema version, {(joint order, metrics version)}, recovered trials) of a shard."""
    with Store.open(path, writer=True, key=key) as store:  # a writer recovers a crashed shard
        recovered = len(store.recovered)
        version = int(store.meta().get("schema_version", SCHEMA_VERSION))
    conn = sqlite3.connect(f"file:{path}?mode=ro", uri=True)
    try:
        kinds = set(conn.execute("SELECT joint_order_json, metrics_version FROM sessions"))
    finally:
        conn.close()
    return version, kinds, recovered


def _signed_by(path: Path) -> str | None:
    """The id of a key that signed some link of the store at ``path`` (None: unsigned)."""
    row = None
    with (
        contextlib.suppress(sqlite3.Error),  # no chain yet, or damaged: opening it says so
        contextlib.closing(sqlite3.connect(f"file:{path}?mode=ro", uri=True)) as conn,
    ):
        row = conn.execute("SELECT key_id FROM chain WHERE key_id IS NOT NULL LIMIT 1").fetchone()
    return None if row is None else str(row[0])


def merge_stores(
    shards: Sequence[Path],
    out: Path,
    progress: Callable[[str], None] | None = None,
    *,
    verify: Literal["output", "shards"] = "output",
    key: ChainKey | None = None,
) -> MergeReport:
    """Copy every shard into ``out`` (created if absent), then verify ``out``; with
    ``verify="shards"``, verify each shard before it is copied instead (what a growing
    store needs: the cost is the shards', not the whole output's). ``key``: the key the
    shards were recorded with, which signs what recovering a crashed shard closes."""
    if not shards:
        raise MergeError("no shards given: name at least one store to merge")
    say = progress or (lambda _: None)
    reference: set[tuple[str, str]] = set()
    recovered = 0
    for shard in shards:
        if not Path(shard).is_file():
            raise MergeError(f"no store at {shard}: give the paths of existing shards")
        if Path(shard).resolve() == Path(out).resolve():
            raise MergeError(f"shard {shard} is the output store: give a different --out")
        signed = _signed_by(Path(shard))
        if key is None and signed:
            raise MergeError(
                f"shard {shard} is signed with key {signed}: give that key (--key FILE) to "
                "merge it, so that the merged store's chain tip is signed too"
            )
        version, kinds, shard_recovered = _compatibility(Path(shard), key)
        recovered += shard_recovered
        if shard_recovered:
            say(f"{shard}: recovered {shard_recovered} trial(s) a dead writer left open")
        if version != SCHEMA_VERSION:
            raise MergeError(
                f"shard {shard} has schema version {version}, this store {SCHEMA_VERSION}: "
                "shards of different schema versions cannot be merged"
            )
        if reference and kinds and kinds != reference:
            raise MergeError(
                f"shard {shard} records frames with another joint order or metrics version "
                "than the shards before it: they cannot share one store"
            )
        reference |= kinds
        if len(reference) > 1:
            raise MergeError(f"shard {shard} mixes joint orders or metrics versions")
        if verify == "shards" and (problems := verify_store(shard)):
            raise MergeError(f"shard {shard} does not verify: {problems[0]}")
    # creates the schema, holds the writer lock; the whole output is checked when it is
    # verified as a whole
    with Store.open(out, writer=True, key=key, check=verify == "output"):
        conn = sqlite3.connect(out, isolation_level=None)
        try:
            conn.execute("PRAGMA foreign_keys = ON")
            for shard in shards:
                _copy(conn, Path(shard), Path(out), key)
                say(f"merged {shard}")
        finally:
            conn.close()
    media = sum(copy_media(Path(shard), Path(out)) for shard in shards)
    if media:
        say(f"copied {media} camera videos into {media_dir_for(Path(out))}")
    findings = verify_store(out) if verify == "output" else []
    if findings:
        raise MergeError(f"merged store {out} does not verify: {findings[0]}")
    with Store.open(out, writer=False) as merged:
        counts = merged.counts()
    if verify == "output":
        # the readers above leave SQLite's -wal and -shm files, which only a connection that
        # may write removes as it closes last: a writer's clean close leaves the store alone
        with Store.open(out, writer=True, key=key, check=False):
            pass
    return MergeReport(len(shards), counts.sessions, counts.trials, counts.frames, recovered, media)


def _copy(conn: sqlite3.Connection, shard: Path, out: Path, key: ChainKey | None) -> None:
    conn.execute("ATTACH DATABASE ? AS shard", (f"file:{shard}?mode=ro",))
    try:
        clash = conn.execute(
            "SELECT count(*) FROM shard.sessions WHERE session_id IN "
            "(SELECT session_id FROM main.sessions)"
        ).fetchone()[0]
        if clash:
            raise MergeError(f"shard {shard} holds sessions that {out} already has: merged before")
        conn.execute("BEGIN IMMEDIATE")
        try:
            for table in TABLE_ORDER:
                conn.execute(f"INSERT INTO main.{table} SELECT * FROM shard.{table}")
            if has_blocks(conn, "shard"):
                conn.execute("INSERT INTO main.frame_blocks SELECT * FROM shard.frame_blocks")
            # heads unchanged; the shard's roots become roots of the output, its tip moves
            conn.execute("INSERT INTO main.chain SELECT * FROM shard.chain ORDER BY rowid")
            conn.execute(
                "INSERT OR IGNORE INTO main.chain_roots SELECT root, store_id, ?, ? "
                "FROM shard.chain_roots",
                (chain_tip.MERGED, time.time()),
            )
            chain_tip.write_tip(conn, key)
            conn.execute("COMMIT")
        except sqlite3.Error as error:
            conn.execute("ROLLBACK")
            raise MergeError(f"could not copy shard {shard} into {out}: {error}") from None
    finally:
        conn.execute("DETACH DATABASE shard")

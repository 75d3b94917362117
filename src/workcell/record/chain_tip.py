"""The two ends of a store's chains: where they may start (its roots) and where they end
now (its tip), so that grafting a session in and cutting the newest links off show.

**Roots.** Every store has an identity (``meta.store_id``). The first session recorded
into a store follows the store's own root, ``sha256(store_id)``, instead of an empty
head, so a session copied in from another store starts from a root this store does not
have. ``chain_roots`` lists the roots a store's chains may start from: its own, those of
the stores merged into it (``workcell merge`` adds them as it copies their chains), and
the empty root of the sessions recorded before schema version 4.

**Tip.** ``meta`` keeps the head of the newest link of the store and the number of links
(``chain_tip_head``, ``chain_tip_links``), rewritten with every link in the same
transaction. Deleting the newest links (cutting a session short, deleting the newest
session) leaves a tip that names a head the store no longer has. With a key the tip is
signed, ``HMAC(key, store_id, head, links, roots)``: it cannot be rewritten to fit the
cut store without the key, and no writer signs on top of a tip that does not fit
(:func:`writer_check`), so whoever holds only a writer with the key cannot have a
truncation re-signed either.

What this cannot show: a store (or its tip) replaced as a whole by an older copy of it,
which holds a tip that fits; only a manifest kept elsewhere shows that.
"""

from __future__ import annotations

import hashlib
import hmac
import sqlite3
import time
from dataclasses import dataclass
from pathlib import Path

from workcell.record.chain_key import ChainKey
from workcell.record.checksum import aggregate_checksum
from workcell.record.errors import StoreError

CREATED, MERGED, MIGRATED = "created", "merged", "migrated"
"""How a root joined a store: its own, copied in by a merge, from before version 4."""
LEGACY_ROOT = ""
"""What the first chains of a store of schema version 3 or older start from."""
TIP_KEYS = ("chain_tip_head", "chain_tip_links", "chain_tip_key_id", "chain_tip_signature")


def store_root(store_id: str) -> str:
    """The head the first chain of the store ``store_id`` follows."""
    return hashlib.sha256(f"workcell/store-root/v1\0{store_id}".encode()).hexdigest()


def store_id(conn: sqlite3.Connection) -> str:
    row = conn.execute("SELECT value FROM meta WHERE key = 'store_id'").fetchone()
    return "" if row is None else str(row[0])


def own_root(conn: sqlite3.Connection) -> str:
    return store_root(store_id(conn))


def declare_root(conn: sqlite3.Connection, root: str, of_store: str, joined: str) -> None:
    """Let chains of this store start from ``root`` (of the store ``of_store``)."""
    conn.execute(
        "INSERT OR IGNORE INTO chain_roots (root, store_id, joined, joined_wall) "
        "VALUES (?, ?, ?, ?)",
        (root, of_store, joined, time.time()),
    )


def roots(conn: sqlite3.Connection) -> dict[str, tuple[str, str]]:
    """root → (the store it is of, how it joined)."""
    rows = conn.execute("SELECT root, store_id, joined FROM chain_roots ORDER BY root")
    return {r[0]: (r[1], r[2]) for r in rows}


@dataclass(frozen=True)
class Tip:
    """The store's chain tip as ``meta`` holds it."""

    head: str
    links: int
    key_id: str | None
    signature: str | None


def read_tip(conn: sqlite3.Connection) -> Tip | None:
    values = dict(
        conn.execute(
            f"SELECT key, value FROM meta WHERE key IN ({', '.join('?' * len(TIP_KEYS))})",
            TIP_KEYS,
        )
    )
    if TIP_KEYS[0] not in values:
        return None
    links = values.get(TIP_KEYS[1], "")
    return Tip(
        values[TIP_KEYS[0]],
        int(links) if links.isdigit() else -1,
        values.get(TIP_KEYS[2]),
        values.get(TIP_KEYS[3]),
    )


def newest(conn: sqlite3.Connection) -> tuple[str, int, str | None]:
    """(head, number of links, signature) of the store's newest link ('', 0, None without
    links)."""
    row = conn.execute("SELECT head, signature FROM chain ORDER BY rowid DESC LIMIT 1").fetchone()
    (count,) = conn.execute("SELECT count(*) FROM chain").fetchone()
    return ("", int(count), None) if row is None else (str(row[0]), int(count), row[1])


def tip_message(conn: sqlite3.Connection, head: str, links: int) -> str:
    """What a tip's signature signs: the store, its newest head and links, its roots."""
    found = roots(conn)
    digest = aggregate_checksum(
        "chain-roots", (list(found), [f"{s}/{joined}" for s, joined in found.values()])
    )
    return f"workcell/chain-tip/v1\0{store_id(conn)}\0{head}\0{links}\0{digest}"


def write_tip(conn: sqlite3.Connection, key: ChainKey | None) -> None:
    """Set the tip to the store's newest link (in the caller's transaction)."""
    head, links, _ = newest(conn)
    values = [(TIP_KEYS[0], head), (TIP_KEYS[1], str(links))]
    conn.execute("DELETE FROM meta WHERE key IN (?, ?)", TIP_KEYS[2:])
    if key is not None:
        values += [
            (TIP_KEYS[2], key.key_id),
            (TIP_KEYS[3], key.sign(tip_message(conn, head, links))),
        ]
    conn.executemany("INSERT OR REPLACE INTO meta (key, value) VALUES (?, ?)", values)


def _short(head: str) -> str:
    return head[:12] + "…" if head else "(none)"


def tip_problem(conn: sqlite3.Connection, key: ChainKey | None) -> tuple[str, bool] | None:
    """What is wrong with the store's tip (with ``key``: also its signature), and whether it
    shows tampering (a writer refuses to write after it) or only a missing signature."""
    tip = read_tip(conn)
    head, links, signature = newest(conn)
    if tip is None:
        if not links:
            return None
        return f"the store holds {links} chain links but no chain tip: it was deleted", True
    if (tip.head, tip.links) != (head, links):
        return (
            f"the store's chain tip is head {_short(tip.head)} after {tip.links} links, but "
            f"its newest link is {_short(head)} after {links}: its newest links were deleted "
            "(a session cut short, the newest session deleted) or added without the tip",
            True,
        )
    if tip.signature is None:
        if signature is not None:
            return (
                "the store's chain tip is not signed but its newest link is: the tip was "
                "rewritten without the key",
                True,
            )
        if key is not None:
            return "the store's chain tip is not signed: it was written without the key", False
        return None
    if key is None:
        return None
    if tip.key_id != key.key_id:
        return (
            f"the store's chain tip is signed with key {tip.key_id}, not with the key given",
            False,
        )
    if not hmac.compare_digest(tip.signature, key.sign(tip_message(conn, head, links))):
        return (
            "the store's chain tip does not match its signature: the tip, the store's "
            "identity or its chain roots were rewritten without the key",
            True,
        )
    return None


def writer_check(conn: sqlite3.Connection, path: Path, key: ChainKey | None) -> bool:
    """Refuse (:class:`StoreError`) to write after a tip that shows tampering; whether
    ``key`` vouches for the store as it is (the tip is signed with it), so that what crash
    recovery closes may be signed with it."""
    problem = tip_problem(conn, key)
    if problem is not None and problem[1]:
        raise StoreError(
            f"store {path}: {problem[0]}; nothing was written: run 'workcell verify --store "
            f"{path}' and record into another store"
        )
    tip = read_tip(conn)
    return problem is None and key is not None and tip is not None and tip.key_id == key.key_id

"""Verifying the hash chains of a store, and a store against an export's manifest.

For every session: its links are whole (positions 0..n-1, each following the one before,
each head recomputed from its fields), link 0 commits to the session row as it was
created and follows a head that exists in the store (else a session was deleted), there
is one trial link per closed trial in ``trial_index`` order, each committing to its
trial's row (hence every frame and event of the trial), frame block and the
session-level events of its range, and a closed session ends with a link committing to
its closed row. A chain starts from another session's head or from a root of the store
(its own, or of a store merged into it: a session copied in from elsewhere does not), no
two sessions start from the same point, and the store's chain tip names its newest link
(:mod:`workcell.record.chain_tip`). With a key, every link and the tip must be signed by
it. Against a manifest, every
session it lists must still be in the store with the head it had when it was exported.

What this cannot show, and the README says so: a store rewritten as a whole with this
project's own functions (rows, checksums and chains recomputed) verifies, unless the
chains were signed with a key the rewriter lacks or a manifest kept elsewhere pins the
heads; the deletion of the newest links with the tip rewritten to fit shows only with the
key or such a manifest, and a store replaced by an older copy of itself only against a
manifest.
"""

from __future__ import annotations

import hmac
import sqlite3
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any

from workcell.record import chain, chain_tip, rowio
from workcell.record.batch import RowBatch
from workcell.record.chain import END, START, TRIAL, ChainKey, Link
from workcell.record.schema import SESSIONS

HEAD_DIGITS, HEX = 64, "0123456789abcdef"
Report = Callable[[str, str, str], None]
"""``report(table, row, problem)``."""


@dataclass
class ChainStats:
    """What the chains of a store hold (for ``workcell verify``'s summary)."""

    sessions: int = 0
    links: int = 0
    signed: int = 0
    key_ids: set[str] = field(default_factory=set)
    migrated_sessions: int = 0


def _short(head: str) -> str:
    return head[:12] + "…" if head else "(none)"


def check_chains(
    conn: sqlite3.Connection, report: Report, key: ChainKey | None = None
) -> ChainStats:
    """Report every problem of every session's chain; what the chains hold."""
    stats = ChainStats()
    meta = dict(conn.execute("SELECT key, value FROM meta"))
    migrated_wall = float(meta["migrated_wall"]) if "migrated_wall" in meta else None
    by_session: dict[str, list[Link]] = {}
    for link in chain.links(conn):
        by_session.setdefault(link.session_id, []).append(link)
    heads = {link.head: link.session_id for links in by_session.values() for link in links}
    roots = chain_tip.roots(conn)
    if chain_tip.own_root(conn) not in roots:
        report("chain", "roots", "the store's own root is not among its chain roots: its "
               "identity (meta store_id) or its roots were rewritten")  # fmt: skip
    started: dict[str, str] = {}
    for row in rowio.select(conn, SESSIONS, order="created_wall, session_id"):
        session_id = row["session_id"]
        links = by_session.pop(session_id, [])
        stats.sessions += 1
        stats.links += len(links)
        if migrated_wall is not None and row["created_wall"] < migrated_wall:
            stats.migrated_sessions += 1
        _SessionChain(conn, row, links, report).check(heads, roots)
        _check_signatures(links, key, report, stats)
        if links and links[0].position == 0 and links[0].previous != chain_tip.LEGACY_ROOT:
            other = started.setdefault(links[0].previous, session_id)
            if other != session_id:
                report(
                    "chain",
                    f"session {session_id} link 0",
                    f"starts from {_short(links[0].previous)} as session {other} does: two "
                    "chains grow from one point, so one of them was copied in from another "
                    "copy of this store",
                )
    tip = chain_tip.tip_problem(conn, key)
    if tip is not None:
        report("chain", "tip", tip[0])
    for session_id, links in by_session.items():
        report(
            "chain",
            f"session {session_id}",
            f"{len(links)} chain links of a session that is not in the store: the session "
            "was deleted",
        )
    return stats


def _check_signatures(
    links: list[Link], key: ChainKey | None, report: Report, stats: ChainStats
) -> None:
    for link in links:
        where = f"session {link.session_id} link {link.position}"
        if link.signature is not None:
            stats.signed += 1
            stats.key_ids.add(str(link.key_id))
        if key is None:
            continue
        if link.signature is None:
            report(
                "chain",
                where,
                "not signed: written without the key (or recomputed since); its content "
                "is not vouched for by the key",
            )
        elif link.key_id != key.key_id:
            report("chain", where, f"signed with key {link.key_id}, not with the key given")
        elif not hmac.compare_digest(link.signature, key.sign(link.head)):
            report(
                "chain",
                where,
                "signature does not match its head: the chain was recomputed without the key",
            )


class _SessionChain:
    """The checks of one session's chain."""

    def __init__(
        self, conn: sqlite3.Connection, row: dict[str, Any], links: list[Link], report: Report
    ) -> None:
        self.conn = conn
        self.row = row
        self.session_id = str(row["session_id"])
        self.links = links
        self.report = report

    def add(self, problem: str, position: int | None = None) -> None:
        where = f"session {self.session_id}"
        self.report("chain", where if position is None else f"{where} link {position}", problem)

    def check(self, heads: Mapping[str, str], roots: Mapping[str, object]) -> None:
        if not self.links:
            self.add("has no hash chain: its links were deleted")
            return
        if not self._whole():
            return  # later checks would only repeat what is broken
        self._start(heads, roots)
        self._trials()
        self._end()

    def _whole(self) -> bool:
        """Positions 0..n-1, each link following the one before, each head its own."""
        whole = True
        for i, link in enumerate(self.links):
            if link.position != i:
                self.add(f"positions jump from {i - 1} to {link.position}: links were deleted")
                return False
            if link.head != link.expected_head():
                self.add("its head is not the hash of its content: the link was altered", i)
                whole = False
            if i and link.previous != self.links[i - 1].head:
                self.add(
                    f"does not follow link {i - 1} (it names head {_short(link.previous)}): "
                    "links were removed, inserted or reordered",
                    i,
                )
                whole = False
        return whole

    def _start(self, heads: Mapping[str, str], roots: Mapping[str, object]) -> None:
        first = self.links[0]
        if first.kind != START or first.subject_id != self.session_id:
            self.add(f"link 0 is a {first.kind} link of {first.subject_id}, not the start", 0)
            return
        created = chain.created_session_checksum(self.row)
        if self._row_intact() and first.digest != chain.start_digest(created):
            self.add(
                "the session row is not the one its chain started with: a value set at its "
                "start (mode, parameters, seed, operator, created_wall ...) was changed",
                0,
            )
        owner = heads.get(first.previous)
        if owner not in (None, self.session_id) or first.previous in roots:
            return
        if first.previous == chain_tip.LEGACY_ROOT:
            self.add(
                "its chain starts from an empty head, as chains recorded before schema "
                "version 4 did, in a store that has none: it was copied in from another store",
                0,
            )
            return
        self.add(
            f"its chain follows head {_short(first.previous)}, which is neither another "
            "session's head nor a root of this store or of a store merged into it: the "
            "session recorded before it was deleted or rewritten, or this session was "
            "copied in from another store",
            0,
        )

    def _row_intact(self) -> bool:
        """Whether the session row matches its own checksum (if not, that is reported as a
        checksum mismatch already, and the chain would only say it again)."""
        (stored,) = self.conn.execute(
            "SELECT checksum FROM sessions WHERE session_id = ?", (self.session_id,)
        ).fetchone()
        return bool(RowBatch.from_mappings(SESSIONS, [self.row]).checksums()[0] == stored)

    def _events(self, after: int, through: int) -> list[str]:
        return chain.session_events(self.conn, self.session_id, after, through)

    def _trials(self) -> None:
        closed = self.conn.execute(
            "SELECT trial_id, trial_index, checksum FROM trials WHERE session_id = ? AND "
            "outcome IS NOT NULL ORDER BY trial_index",
            (self.session_id,),
        ).fetchall()
        links = [link for link in self.links if link.kind == TRIAL]
        linked = [link.subject_id for link in links]
        expected = [t[0] for t in closed]
        if linked != expected:
            missing = [t for t in linked if t not in expected]
            unlinked = [t for t in expected if t not in linked]
            detail = (
                f"linked trials not in the store (deleted): {missing}; "
                if missing
                else f"closed trials without a link (added): {unlinked}; "
                if unlinked
                else ""
            )
            self.add(
                f"its trial links are not its closed trials in trial_index order: {detail}"
                "trials were deleted, added or reordered"
            )
        checksums = {t[0]: t[2] for t in closed}
        after = -1
        for link in self.links:
            if link.events_through < after:
                self.add("events_through goes back: links were reordered", link.position)
            if link.kind == TRIAL and link.subject_id in checksums:
                block = self.conn.execute(
                    "SELECT checksum FROM frame_blocks WHERE trial_id = ?", (link.subject_id,)
                ).fetchone()
                digest = chain.trial_digest(
                    checksums[link.subject_id],
                    None if block is None else block[0],
                    self._events(after, link.events_through),
                )
                if digest != link.digest:
                    self.add(
                        f"trial {link.subject_id} is not what its link committed to: its row, "
                        "a frame or event of it, its frame block or a session event changed",
                        link.position,
                    )
            after = max(after, link.events_through)

    def _end(self) -> None:
        last = self.links[-1]
        running = self.row["status"] == "running"
        ends = [link for link in self.links if link.kind == END]
        if running:
            if ends:
                self.add("has an end link but the session is running", ends[0].position)
            return
        if last.kind != END or last.subject_id != self.session_id:
            self.add("the session is closed but its chain has no end link: it was cut short")
            return
        after = max((link.events_through for link in self.links[:-1]), default=-1)
        (session_checksum,) = self.conn.execute(
            "SELECT checksum FROM sessions WHERE session_id = ?", (self.session_id,)
        ).fetchone()
        events = self._events(after, last.events_through)
        if last.digest != chain.end_digest(session_checksum, events):
            self.add(
                "the closed session is not what its end link committed to: its row, a "
                "session event or the set of its trials changed",
                last.position,
            )
        (later,) = self.conn.execute(
            "SELECT count(*) FROM events WHERE session_id = ? AND seq > ?",
            (self.session_id, last.events_through),
        ).fetchone()
        if later:
            self.add(f"{later} events were added after the session ended", last.position)


def check_manifest(
    conn: sqlite3.Connection, manifest: Mapping[str, Any], where: str, report: Report
) -> int:
    """Compare the store with the chain heads of an export's manifest; returns how many
    sessions the manifest pins."""
    sessions = manifest.get("sessions")
    if not isinstance(sessions, Mapping):
        report("manifest", where, "has no 'sessions': not an export manifest")
        return 0
    pinned = 0
    for session_id, entry in sessions.items():
        pinned_chain = entry.get("chain") if isinstance(entry, Mapping) else None
        label = f"session {session_id}"
        if not isinstance(pinned_chain, Mapping):
            report("manifest", label, "carries no chain head (exported before hash chains)")
            continue
        count, head = pinned_chain.get("links"), pinned_chain.get("head")
        if type(count) is not int or count < 1 or not _is_head(head):
            report(
                "manifest",
                label,
                f"its chain entry is malformed (links {count!r:.20}, head {head!r:.20}): "
                "links must be a whole number of at least 1 and head 64 hex digits",
            )
            continue
        pinned += 1
        links = chain.links(conn, str(session_id))
        if not links:
            report(
                "manifest",
                label,
                f"is in the export {where} but not in the store: deleted since the export",
            )
            continue
        if count > len(links) or links[count - 1].head != head:
            now = links[min(count, len(links)) - 1].head
            report(
                "manifest",
                label,
                f"differs from the export {where}: its chain head there is {_short(str(head))}, "
                f"here {_short(now)} — the session's record changed since it was exported",
            )
    if not sessions:
        report(
            "manifest",
            where,
            "pins no session's chain head, so it vouches for nothing: give the manifest.json "
            "of an export that holds sessions (exported since hash chains)",
        )
    return pinned


def _is_head(value: object) -> bool:
    return isinstance(value, str) and len(value) == HEAD_DIGITS and set(value) <= set(HEX)


def manifest_entry(links: list[Link]) -> dict[str, Any]:
    """What a manifest records of one session's chain: its head and length, whether it is
    complete (the session closed) and which key signed it."""
    last = links[-1]
    return {
        "head": last.head,
        "links": len(links),
        "closed": last.kind == END,
        "key_id": last.key_id,
    }

"""``verify``: is a store (or a CSV export) whole and unchanged since it was written?

A store is checked for its schema, SQLite integrity and foreign keys, the vocabulary of
outcomes and statuses, every row's content checksum and every closed trial's and
session's aggregate checksum, frame counts against trial rows, frame indices without gaps,
monotonic timestamps and finite values (NULL only where it is legitimate), and every
session's hash chain (:mod:`workcell.record.chain_check`), with a key its signatures, with
an export's manifest the heads it pinned. Each problem is one :class:`IntegrityFinding` naming the
store, the table and the row. A store a recorder is writing can be verified: its running
trial is not a problem then.
"""

from __future__ import annotations

import json
import math
import os
import sqlite3
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from workcell.record import lifecycle, rowio
from workcell.record.chain import ChainKey
from workcell.record.chain_check import ChainStats, check_chains, check_manifest
from workcell.record.columns import (
    ANNOTATION_KINDS,
    INTERRUPTION_REASONS,
    OUTCOMES,
    SESSION_STATUSES,
)
from workcell.record.connection import connect, damage_as_store_error, writer_active
from workcell.record.export_check import verify_export
from workcell.record.findings import IntegrityFinding
from workcell.record.frame_check import check_trial_frames
from workcell.record.layout import TableLayout
from workcell.record.schema import (
    ANNOTATIONS,
    EVENTS,
    LAYOUTS,
    SCHEMA_VERSION,
    SESSIONS,
    TRIALS,
    quote,
)
from workcell.sim.joints import JOINT_ORDER

__all__ = ["ChainStats", "IntegrityFinding", "verify_export", "verify_store", "verify_store_report"]

RECOVER_HINT = "run 'workcell verify --recover --store PATH' to close it as crash_recovered"


def verify_store(
    path: str | os.PathLike[str],
    *,
    key: ChainKey | None = None,
    manifest: Mapping[str, Any] | None = None,
) -> list[IntegrityFinding]:
    """Every problem found in the store at ``path`` (empty when it verifies); with
    ``key``, every chain link must carry its signature; with an export's ``manifest``,
    every session it lists must still have the chain head it had then.

    Raises :class:`StoreError` when the file is missing, not a store, or of a schema this
    Workcell does not read.
    """
    return verify_store_report(path, key=key, manifest=manifest)[0]


def verify_store_report(
    path: str | os.PathLike[str],
    *,
    key: ChainKey | None = None,
    manifest: Mapping[str, Any] | None = None,
) -> tuple[list[IntegrityFinding], ChainStats]:
    """:func:`verify_store`, and what the store's chains hold."""
    path = Path(path)
    conn = connect(path, writer=False)
    try:
        conn.execute("BEGIN")  # one snapshot for every check, even while a recorder writes
        verifier = _Verifier(path, conn)
        with damage_as_store_error(path):
            if not verifier.intact():
                return verifier.findings, ChainStats()  # a damaged file's rows mean nothing
            findings = verifier.run()
            stats = check_chains(conn, verifier.add, key)
            if manifest is not None:
                check_manifest(conn, manifest, "manifest", verifier.add)
        return findings, stats
    finally:
        conn.close()


class _Verifier:
    def __init__(self, path: Path, conn: sqlite3.Connection) -> None:
        self.path = path
        self.conn = conn
        self.live = writer_active(path)
        self.findings: list[IntegrityFinding] = []

    def add(self, table: str, row: str, problem: str) -> None:
        self.findings.append(IntegrityFinding(str(self.path), table, row, problem))

    def intact(self) -> bool:
        """SQLite's quick check of the file; a damaged one is one finding."""
        (first,) = self.conn.execute("PRAGMA quick_check(1)").fetchone()
        if first != "ok":
            self.add(
                "database",
                "",
                f"the file is damaged (SQLite's integrity check: {' '.join(first.split())}); "
                "nothing else was read from it: restore it from a copy",
            )
        return bool(first == "ok")

    def run(self) -> list[IntegrityFinding]:
        if not self.check_schema():
            return self.findings  # rows of an unknown shape cannot be read reliably
        self.check_database()
        for layout in (SESSIONS, TRIALS, EVENTS, ANNOTATIONS):
            self.check_checksums(layout)
        self.check_sessions()
        trials = rowio.select(self.conn, TRIALS, order="started_wall, trial_index")
        self.check_trials(trials)
        self.check_events()
        self.check_annotations()
        for trial in trials:
            label = f"trial {trial['trial_id']}"
            count = check_trial_frames(self.conn, trial["trial_id"], self.add)
            if trial["outcome"] is not None and trial["n_frames"] != count:
                self.add(
                    "trials",
                    label,
                    f"n_frames is {trial['n_frames']} but {count} frames are stored",
                )
        return self.findings

    def check_schema(self) -> bool:
        meta = dict(self.conn.execute("SELECT key, value FROM meta"))
        if meta.get("schema_version") != str(SCHEMA_VERSION):
            self.add(
                "meta",
                "schema_version",
                f"is {meta.get('schema_version')!r}, "
                f"expected {SCHEMA_VERSION} (as in PRAGMA user_version)",
            )
        whole = True
        for layout in LAYOUTS:
            info = self.conn.execute(f"PRAGMA table_info({quote(layout.name)})").fetchall()
            found = [(row[1], row[2]) for row in info]
            expected = [(name, kind.upper()) for name, kind in layout.stored]
            if found != expected:
                whole = False
                missing = [n for n, _ in expected if (n, _) not in found]
                extra = [n for n, _ in found if (n, _) not in expected]
                self.add(
                    layout.name,
                    "",
                    f"columns differ from schema version "
                    f"{SCHEMA_VERSION} (missing or retyped: {missing}; unknown: {extra})",
                )
        return whole

    def check_database(self) -> None:
        for (message,) in self.conn.execute("PRAGMA integrity_check"):
            if message != "ok":
                self.add("database", "", f"SQLite integrity check: {message}")
        for table, rowid, parent, _ in self.conn.execute("PRAGMA foreign_key_check"):
            layout = next((x for x in LAYOUTS if x.name == table), None)
            if layout is None:  # frame_blocks, chain
                self.add(table, f"rowid {rowid}", f"refers to a missing row of {parent}")
                continue
            key = self.conn.execute(
                f"SELECT {', '.join(quote(k) for k in layout.key)} FROM {quote(table)} "
                "WHERE rowid = ?",
                (rowid,),
            ).fetchone()
            self.add(table, _label(layout, key), f"refers to a missing row of {parent}")

    def check_checksums(self, layout: TableLayout) -> None:
        for batch, stored, keys in rowio.select_grouped(self.conn, layout):
            for key, expected, actual in zip(keys, stored, batch.checksums(), strict=True):
                if expected != actual:
                    self.add(
                        layout.name,
                        _label(layout, key),
                        "checksum mismatch: the row was changed after it was written",
                    )

    def check_sessions(self) -> None:
        for row in rowio.select(self.conn, SESSIONS):
            label = f"session {row['session_id']}"
            status = row["status"]
            if status not in SESSION_STATUSES:
                self.add("sessions", label, f"status {status!r} is not one of {SESSION_STATUSES}")
            if not 1 <= row["schema_version"] <= SCHEMA_VERSION:  # as it was recorded
                self.add(
                    "sessions",
                    label,
                    f"schema_version {row['schema_version']} is not 1 to {SCHEMA_VERSION}",
                )
            for name in ("parameters_json", "thresholds_json", "metric_definitions_json"):
                if _json(row[name]) is None:
                    self.add("sessions", label, f"{name} is not valid JSON")
            if _json(row["joint_order_json"]) != list(JOINT_ORDER):
                self.add("sessions", label, "joint_order_json is not the frame columns' order")
            self.check_finite("sessions", label, row, ("created_wall", "ended_wall"))
            if status == "running":
                if not self.live:
                    self.add(
                        "sessions",
                        label,
                        f"still running but no recorder holds the store; {RECOVER_HINT}",
                    )
            elif row["content_checksum"] != lifecycle.session_content_checksum(
                self.conn, row["session_id"]
            ):
                self.add(
                    "sessions",
                    label,
                    "aggregate checksum mismatch: a trial or "
                    "session event was changed, added or removed",
                )

    def check_trials(self, trials: list[dict[str, Any]]) -> None:
        reals = TRIALS.of_kind("real")
        for row in trials:
            label = f"trial {row['trial_id']}"
            outcome, reason = row["outcome"], row["interruption_reason"]
            self.check_finite("trials", label, row, reals)
            if row["included"] not in (None, 0, 1):
                self.add("trials", label, f"included is {row['included']}, not 0 or 1")
            if outcome is None:
                if not self.live:
                    self.add(
                        "trials",
                        label,
                        f"still running but no recorder holds the store; {RECOVER_HINT}",
                    )
                continue
            if outcome not in OUTCOMES:
                self.add("trials", label, f"outcome {outcome!r} is not one of {OUTCOMES}")
            elif outcome == "interrupted" and reason not in INTERRUPTION_REASONS:
                self.add(
                    "trials",
                    label,
                    f"interruption_reason {reason!r} is not one of {INTERRUPTION_REASONS}",
                )
            elif outcome != "interrupted" and reason is not None:
                self.add("trials", label, f"interruption_reason {reason!r} on a {outcome} trial")
            if row["content_checksum"] != lifecycle.trial_content_checksum(
                self.conn, row["trial_id"]
            ):
                self.add(
                    "trials",
                    label,
                    "aggregate checksum mismatch: a frame or event "
                    "of the trial was changed, added or removed",
                )

    def check_events(self) -> None:
        rows = rowio.select(self.conn, EVENTS, order="session_id, seq")
        expected_seq: dict[str, int] = {}
        last_wall: dict[str, float] = {}
        last_sim: dict[str, float] = {}
        for row in rows:
            label = f"event {row['event_id']}"
            session, trial = row["session_id"], row["trial_id"]
            seq = expected_seq.get(session, 0)
            if row["seq"] != seq:
                self.add(
                    "events",
                    label,
                    f"seq {row['seq']} of session {session} follows {seq - 1}: events are missing",
                )
            expected_seq[session] = row["seq"] + 1
            self.check_finite("events", label, row, ("t_sim", "t_wall"))
            if row["t_wall"] < last_wall.get(session, -math.inf):
                self.add("events", label, "t_wall goes back in time")
            last_wall[session] = row["t_wall"]
            if trial is not None and row["t_sim"] is not None:
                if row["t_sim"] < last_sim.get(trial, -math.inf):
                    self.add("events", label, "t_sim goes back in time")
                last_sim[trial] = row["t_sim"]
            if _json(row["payload_json"]) is None:
                self.add("events", label, "payload_json is not valid JSON")

    def check_annotations(self) -> None:
        for row in rowio.select(self.conn, ANNOTATIONS):
            label = f"annotation {row['annotation_id']}"
            if row["kind"] not in ANNOTATION_KINDS:
                self.add(
                    "annotations", label, f"kind {row['kind']!r} is not one of {ANNOTATION_KINDS}"
                )
            self.check_finite("annotations", label, row, ("at_wall",))

    def check_finite(
        self, table: str, label: str, row: dict[str, Any], names: tuple[str, ...]
    ) -> None:
        for name in names:
            value = row[name]
            if value is not None and not math.isfinite(value):
                self.add(table, label, f"{name} is {value}")


def _label(layout: TableLayout, key: Any) -> str:
    if layout.name == "frames":
        trial_id, index = key
        return f"trial {trial_id} frame {index}"
    value = key[0] if isinstance(key, tuple) else key
    return f"{layout.name.removesuffix('s')} {value}"


def _json(text: str) -> Any:
    try:
        return json.loads(text)
    except (TypeError, ValueError):
        return None

"""CSV export of a store, and reading such an export back.

``export_csv`` writes sessions.csv, trials.csv, events.csv, frames.csv (exactly the
interchange contract's columns) and annotations.csv, then manifest.json: schema and
software version, each session's parameters, thresholds, metric definitions and hash-chain
head as stored, the joint order, the column lists, and the sha256, size and row count of
every file. Kept apart from the store, the manifest pins each session's record as it was
exported (``workcell verify --store S --manifest M``). It
reads one consistent snapshot of the store (a recorder may keep writing) and streams the
frames trial by trial, so memory does not grow with the store.
"""

from __future__ import annotations

import csv
import json
import os
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from workcell import __version__
from workcell.record import chain
from workcell.record.batch import RowBatch
from workcell.record.chain_check import manifest_entry
from workcell.record.connection import connect
from workcell.record.csv_format import (
    FILES,
    FORMAT,
    FORMAT_VERSION,
    MANIFEST,
    file_sha256,
    format_row,
    known_header,
    parse_row,
)
from workcell.record.entries import SessionRecord
from workcell.record.errors import ExportError
from workcell.record.rowio import FETCH_ROWS, select
from workcell.record.schema import SCHEMA_VERSION, SESSIONS, column_list, quote
from workcell.sim.joints import JOINT_ORDER

Progress = Callable[[int, int], None]
"""``progress(frames_written, frames_total)``."""

_ORDER = {
    "sessions.csv": "created_wall, session_id",
    "trials.csv": "started_wall, trial_index",
    "events.csv": "(SELECT created_wall FROM sessions s WHERE s.session_id = events.session_id), "
    "session_id, seq",
    "annotations.csv": "at_wall, annotation_id",
}


@dataclass(frozen=True)
class CsvExport:
    """An export read back: the manifest and each file as columns (see
    ``RowBatch.to_columns`` for the dtypes), keyed by file name."""

    manifest: dict[str, Any]
    tables: dict[str, dict[str, NDArray[Any]]]


def export_csv(
    store_path: str | os.PathLike[str],
    out_dir: str | os.PathLike[str],
    progress: Progress | None = None,
) -> dict[str, Any]:
    """Export the store at ``store_path`` into ``out_dir`` (new or empty); returns the
    manifest written."""
    store_path, out = Path(store_path), Path(out_dir)
    if out.exists() and (not out.is_dir() or any(out.iterdir())):
        raise ExportError(
            f"output {out} exists and is not an empty directory; give a new or empty directory"
        )
    conn = connect(store_path, writer=False, check=True)
    try:
        conn.execute("BEGIN")  # one snapshot for every file
        out.mkdir(parents=True, exist_ok=True)
        rows: dict[str, int] = {}
        for name, layout in FILES.items():
            if name == "frames.csv":
                continue
            sql = (
                f"SELECT {column_list(layout.names)} FROM {quote(layout.name)} "
                f"ORDER BY {_ORDER[name]}"
            )
            rows[name] = _write_csv(out / name, layout.names, [conn.execute(sql)])
        rows["frames.csv"] = _write_frames(conn, out / "frames.csv", progress)
        sessions = [SessionRecord.from_row(r) for r in select(conn, SESSIONS)]
        chains: dict[str, list[chain.Link]] = {}
        for link in chain.links(conn):
            chains.setdefault(link.session_id, []).append(link)
        meta = dict(conn.execute("SELECT key, value FROM meta"))
        open_trials = [
            r[0]
            for r in conn.execute(
                "SELECT trial_id FROM trials WHERE outcome IS NULL ORDER BY started_wall"
            )
        ]
    finally:
        conn.close()
    manifest = {
        "format": FORMAT,
        "format_version": FORMAT_VERSION,
        "schema_version": SCHEMA_VERSION,
        "software_version": __version__,
        "store": {
            "path": str(store_path),
            "store_id": meta.get("store_id"),
            "software_version": meta.get("software_version"),
        },
        "exported_wall": time.time(),
        "joint_order": list(JOINT_ORDER),
        "sessions": {
            s.session_id: {
                "mode": s.mode,
                "software_version": s.software_version,
                "parameters": s.parameters,
                "thresholds": s.thresholds,
                "metric_definitions": s.metric_definitions,
                "metrics_version": s.metrics_version,
                "joint_order": list(s.joint_order),
                "chain": manifest_entry(chains[s.session_id]) if s.session_id in chains else None,
            }
            for s in sessions
        },
        "open_trials": open_trials,
        "columns": {name: list(layout.names) for name, layout in FILES.items()},
        "files": {
            name: {
                "sha256": file_sha256(out / name),
                "bytes": (out / name).stat().st_size,
                "rows": rows[name],
            }
            for name in FILES
        },
    }
    (out / MANIFEST).write_text(json.dumps(manifest, indent=2, sort_keys=True) + "\n")
    return manifest


def read_csv_export(out_dir: str | os.PathLike[str]) -> CsvExport:
    """Read an export back: every file as columns, values exactly as exported."""
    out = Path(out_dir)
    try:
        manifest = json.loads((out / MANIFEST).read_text())
    except (OSError, ValueError) as error:
        raise ExportError(
            f"{out / MANIFEST}: cannot be read ({error}); is {out} a Workcell CSV export?"
        ) from None
    tables = {}
    for name, layout in FILES.items():
        with (out / name).open(newline="") as file:
            reader = csv.reader(file)
            header = next(reader, [])
            if not known_header(layout, header):
                raise ExportError(f"{out / name}: the header is not the contract's columns")
            values = [parse_row(layout, cells) for cells in reader]
        tables[name] = RowBatch.from_grouped(layout, values).to_columns()
    return CsvExport(manifest, tables)


def _write_csv(path: Path, header: tuple[str, ...], cursors: list[Any]) -> int:
    count = 0
    with path.open("w", newline="") as file:
        writer = csv.writer(file, lineterminator="\n")
        writer.writerow(header)
        for cursor in cursors:
            while chunk := cursor.fetchmany(FETCH_ROWS):
                writer.writerows(format_row(row) for row in chunk)
                count += len(chunk)
    return count


def _write_frames(conn: Any, path: Path, progress: Progress | None) -> int:
    layout = FILES["frames.csv"]
    total = conn.execute("SELECT count(*) FROM frames").fetchone()[0]
    trials = [
        r[0] for r in conn.execute("SELECT trial_id FROM trials ORDER BY started_wall, trial_index")
    ]
    sql = f"SELECT {column_list(layout.names)} FROM frames WHERE trial_id = ? ORDER BY frame_index"
    count = 0
    with path.open("w", newline="") as file:
        writer = csv.writer(file, lineterminator="\n")
        writer.writerow(layout.names)
        for trial_id in trials:
            cursor = conn.execute(sql, (trial_id,))
            while chunk := cursor.fetchmany(FETCH_ROWS):
                writer.writerows(format_row(row) for row in chunk)
                count += len(chunk)
                if progress is not None:
                    progress(count, total)
    return count


def columns_equal(a: NDArray[Any], b: NDArray[Any]) -> bool:
    """Exact equality of two columns, NaN equal to NaN (for round-trip checks)."""
    if a.dtype.kind == "f" and b.dtype.kind == "f":
        return bool(np.array_equal(a, b, equal_nan=True))
    return bool(np.array_equal(a, b))

"""Reading a CSV export for an audit: the small files whole, frames.csv streamed.

Cells are read exactly as exported (reals are written with ``repr``, so they parse back
bit for bit; an empty cell is NULL and becomes NaN), so an audit of an export sees the
same numbers as an audit of the store it came from.
"""

from __future__ import annotations

import csv
import json
import operator
from collections.abc import Callable, Collection, Iterator
from pathlib import Path
from typing import Any, Literal

import numpy as np

from workcell.audit.errors import AuditError
from workcell.audit.rows import SessionRow, TrialRow
from workcell.audit.source import (
    FRAME_COLUMNS_READ,
    MIDPOINT_COLUMNS,
    SWITCH_KINDS,
    FloatArray,
    Pauses,
    Switches,
    midpoint_xy,
    pause_of,
)
from workcell.audit.task_stages import STAGE_COLUMNS, StageFrames, stage_frames, started_conditions
from workcell.metrics import FrameArrays
from workcell.record.csv_format import FILES, MANIFEST, known_header, parse_row
from workcell.record.entries import AnnotationRecord

Rows = list[tuple[str, ...]]


class CsvSource:
    """A directory written by ``workcell export --format csv``."""

    kind: Literal["csv"] = "csv"

    def __init__(self, path: Path) -> None:
        self.path = path
        if not (path / MANIFEST).is_file():
            raise AuditError(
                f"{path} holds no {MANIFEST}: give a directory written by "
                "'workcell export --format csv'"
            )

    def sessions(self) -> list[SessionRow]:
        rows = sorted(
            self._table("sessions.csv"), key=lambda r: (r["created_wall"], r["session_id"])
        )
        return [
            SessionRow.parse(
                row, json.loads(row["parameters_json"]), json.loads(row["thresholds_json"])
            )
            for row in rows
        ]

    def trials(self) -> list[TrialRow]:
        return [TrialRow.parse(row) for row in self._table("trials.csv")]

    def annotations(self) -> list[AnnotationRecord]:
        return [AnnotationRecord.from_row(row) for row in self._table("annotations.csv")]

    def frames(self) -> Iterator[tuple[str, FrameArrays]]:
        for trial_id, rows in self._frame_groups(FRAME_COLUMNS_READ, None):
            yield trial_id, FrameArrays.from_matrix(_floats(rows, self.path, trial_id))

    def midpoints(self, trial_ids: Collection[str]) -> dict[str, FloatArray]:
        wanted = set(trial_ids)
        return {
            trial_id: midpoint_xy(_floats(rows, self.path, trial_id))
            for trial_id, rows in self._frame_groups(MIDPOINT_COLUMNS, wanted)
        }

    def stage_frames(self, trial_ids: Collection[str]) -> dict[str, StageFrames]:
        return {
            trial_id: stage_frames(rows)
            for trial_id, rows in self._frame_groups(STAGE_COLUMNS, set(trial_ids))
        }

    def trial_conditions(self, trial_ids: Collection[str]) -> dict[str, dict[str, object]]:
        wanted = set(trial_ids)
        out: dict[str, dict[str, object]] = {}
        for row in self._table("events.csv"):
            if row["kind"] == "trial_started" and row["trial_id"] in wanted:
                out[row["trial_id"]] = started_conditions(row["payload_json"] or "")
        return out

    def trial_pauses(self, trial_ids: Collection[str]) -> dict[str, Pauses]:
        wanted = set(trial_ids)
        out: dict[str, list[tuple[float, float]]] = {}
        for row in self._table("events.csv"):
            if row["kind"] != "resumed" or row["trial_id"] not in wanted:
                continue
            pause = pause_of(row["t_sim"], row["payload_json"] or "")
            if pause is not None:
                out.setdefault(row["trial_id"], []).append(pause)
        return {trial_id: tuple(pauses) for trial_id, pauses in out.items()}

    def trial_switches(self, trial_ids: Collection[str]) -> dict[str, Switches]:
        wanted = set(trial_ids)
        out: dict[str, list[tuple[str, float]]] = {}
        for row in self._table("events.csv"):
            if row["kind"] not in SWITCH_KINDS or row["trial_id"] not in wanted:
                continue
            if row["t_sim"] is not None:
                out.setdefault(row["trial_id"], []).append((row["kind"], float(row["t_sim"])))
        return {trial_id: tuple(switches) for trial_id, switches in out.items()}

    def close(self) -> None:
        pass

    def _table(self, name: str) -> list[dict[str, Any]]:
        layout = FILES[name]
        path = self.path / name
        try:
            with path.open(newline="") as file:
                reader = csv.reader(file)
                if not known_header(layout, next(reader, [])):
                    raise AuditError(f"{path}: the header is not the contract's columns")
                return [
                    dict(zip(layout.grouped, parse_row(layout, r), strict=True)) for r in reader
                ]
        except OSError as error:
            raise AuditError(f"{path}: cannot be read ({error.strerror})") from None
        except ValueError as error:
            raise AuditError(f"{path}: a cell cannot be read ({error})") from None

    def _frame_groups(
        self, names: tuple[str, ...], wanted: set[str] | None
    ) -> Iterator[tuple[str, Rows]]:
        """Each trial's rows of ``names`` (text cells), trial by trial as in the file."""
        path = self.path / "frames.csv"
        try:
            file = path.open(newline="")
        except OSError as error:
            raise AuditError(f"{path}: cannot be read ({error.strerror})") from None
        with file:
            reader = csv.reader(file)
            header = next(reader, [])
            missing = [n for n in ("trial_id", *names) if n not in header]
            if missing:
                raise AuditError(f"{path}: no column(s) {', '.join(missing)}")
            pick: Callable[[list[str]], tuple[str, ...]] = operator.itemgetter(
                *(header.index(n) for n in names)
            )
            at = header.index("trial_id")
            seen: set[str] = set()
            current = ""
            rows: Rows = []
            for row in reader:
                trial_id = row[at]
                if trial_id != current:
                    if rows:
                        yield current, rows
                    if trial_id in seen:
                        raise AuditError(
                            f"{path}: the frames of trial {trial_id} are not together; "
                            "frames.csv must hold each trial's frames in one run"
                        )
                    seen.add(trial_id)
                    current, rows = trial_id, []
                if wanted is None or trial_id in wanted:
                    rows.append(pick(row))
            if rows:
                yield current, rows


def _floats(rows: Rows, path: Path, trial_id: str) -> FloatArray:
    """Text cells as float64; an empty cell (NULL) is NaN."""
    cells = np.array(rows, dtype=str)
    cells[cells == ""] = "nan"
    try:
        return cells.astype(np.float64)
    except ValueError as error:
        raise AuditError(
            f"{path / 'frames.csv'}: trial {trial_id} holds a cell that is not a number ({error})"
        ) from None

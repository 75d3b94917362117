"""The CSV interchange files: their names, columns and how a cell is written and read.

A NULL is an empty cell (text is never empty in a store: an empty text is NULL). Reals are
written with ``repr`` so they read back bit for bit (``inf`` and ``-inf`` included; NaN is
NULL); integers in decimal; text as is (quoted by the csv module where needed).
"""

from __future__ import annotations

import hashlib
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from workcell.record.columns import (
    ANNOTATION_COLUMNS,
    EVENT_COLUMNS,
    FRAME_COLUMNS,
    SESSION_COLUMNS,
    TRIALS_CSV_COLUMNS,
)
from workcell.record.layout import Appended, TableLayout
from workcell.record.schema import (
    ANNOTATIONS,
    EVENTS,
    FRAMES,
    SESSIONS,
    TRIALS,
)

MANIFEST = "manifest.json"
FORMAT = "workcell-csv"
FORMAT_VERSION = 1


def _sub_layout(layout: TableLayout, names: tuple[str, ...]) -> TableLayout:
    """``layout`` restricted to the exported ``names`` (in that order)."""
    added = tuple(
        Appended(group.version, tuple(n for n in group.names if n in names))
        for group in layout.added
    )
    return TableLayout(
        layout.name,
        tuple(layout.column(n) for n in names),
        layout.key,
        added=tuple(group for group in added if group.names),
    )


FILES: dict[str, TableLayout] = {
    "sessions.csv": _sub_layout(SESSIONS, SESSION_COLUMNS),
    "trials.csv": _sub_layout(TRIALS, TRIALS_CSV_COLUMNS),
    "events.csv": _sub_layout(EVENTS, EVENT_COLUMNS),
    "frames.csv": _sub_layout(FRAMES, FRAME_COLUMNS),
    "annotations.csv": _sub_layout(ANNOTATIONS, ANNOTATION_COLUMNS),
}
"""Every exported file and its columns: exactly the contract's, in its order, then the
columns later schema versions added (frames.csv: the filtered poses since version 3, the
task columns since version 5; trials.csv: the task columns since version 5)."""


def format_row(row: Sequence[Any]) -> list[str]:
    """Cells of one row as SQLite returned it (float, int, str or None)."""
    return ["" if v is None else repr(v) if isinstance(v, float) else str(v) for v in row]


def known_widths(layout: TableLayout) -> tuple[int, ...]:
    """How many columns the file had in each schema version: today's, then those of
    exports made before each version's appended columns existed (newest first)."""
    widths = [len(layout.names)]
    for group in reversed(layout.added):
        widths.append(widths[-1] - len(group.names))
    return tuple(widths)


def known_header(layout: TableLayout, header: Sequence[str]) -> bool:
    """Whether ``header`` is the file's columns: the contract's, or those of an export made
    before some of the layout's appended columns existed (they then read as NULL)."""
    names = tuple(header)
    return any(names == layout.names[:width] for width in known_widths(layout))


def parse_row(layout: TableLayout, cells: Sequence[str]) -> list[Any]:
    """Typed values of one CSV row, in the layout's grouped order (see ``RowBatch``); a row
    of an export made before some appended columns existed holds none of them (NULL)."""
    if len(cells) not in known_widths(layout):
        raise ValueError(f"a row of {len(cells)} cells, not {len(layout.names)}")
    values = dict(zip(layout.names, cells, strict=False))
    out: list[Any] = []
    for name in layout.grouped:
        cell = values.get(name, "")
        kind = layout.column(name).kind
        if cell == "":
            out.append(None)
        elif kind == "real":
            out.append(float(cell))
        elif kind == "integer":
            out.append(int(cell))
        else:
            out.append(cell)
    return out


def file_sha256(path: Path) -> str:
    """Hex sha256 of a file's bytes, read in blocks."""
    h = hashlib.sha256()
    with path.open("rb") as file:
        while block := file.read(1 << 20):
            h.update(block)
    return h.hexdigest()

"""Rows in bulk: values checked and grouped by kind, with their checksums and SQL rows.

One path for every direction: rows handed to the store (mappings or columns), rows read
back from SQLite and cells read from a CSV export all become a :class:`RowBatch`, so the
checksum written is the checksum verified and a columnar read is the same whatever the
source.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from workcell.record.checksum import row_checksums
from workcell.record.errors import RecordError
from workcell.record.layout import TableLayout
from workcell.record.schema import FRAMES

INT64_MIN, INT64_MAX = -(2**63), 2**63 - 1
Columnar = Mapping[str, Any]
"""Column name → sequence or 1-D array of that column's values (all the same length)."""


def as_text(value: object, where: str) -> str | None:
    """A text cell: str, or None for NULL (an empty string is NULL too)."""
    if value is None or value == "":
        return None
    if isinstance(value, str):
        return value
    raise RecordError(f"{where}: expected text, got {type(value).__name__} {value!r}")


def as_int(value: object, where: str) -> int | None:
    """An integer cell: an int (or a float holding an integer), or None / NaN for NULL."""
    if type(value) is int and INT64_MIN <= value <= INT64_MAX:  # the common case, fast
        return value
    if value is None:
        return None
    if isinstance(value, float | np.floating):
        if math.isnan(value):
            return None
        if not float(value).is_integer():
            raise RecordError(f"{where}: expected an integer, got {value!r}")
        number = int(value)
    elif isinstance(value, int | np.integer):
        number = int(value)
    else:
        raise RecordError(f"{where}: expected an integer, got {type(value).__name__} {value!r}")
    if not INT64_MIN <= number <= INT64_MAX:
        raise RecordError(f"{where}: {number} does not fit in 64 bits")
    return number


@dataclass(frozen=True)
class RowBatch:
    """Rows of one table: ``text`` and ``integer`` per row, ``real`` as an (n, k) array with
    NaN for NULL; each in the layout's grouped order (text, real, integer columns)."""

    layout: TableLayout
    text: list[tuple[str | None, ...]]
    real: NDArray[np.float64]
    integer: list[tuple[int | None, ...]]

    def __len__(self) -> int:
        return len(self.text)

    @classmethod
    def from_mappings(
        cls,
        layout: TableLayout,
        rows: Sequence[Mapping[str, object]],
        fixed: Mapping[str, str] | None = None,
    ) -> RowBatch:
        """Rows as mappings with every column of ``layout``; ``fixed`` columns (ids the
        store fills in) may be left out, and must match where given; appended columns
        (:class:`~workcell.record.layout.TableLayout`) may be left out too (NULL)."""
        fixed = fixed or {}
        table = layout.name
        _check_names(layout, rows[0].keys() if rows else (), fixed)
        text_names = layout.of_kind("text")
        real_names = layout.of_kind("real")
        int_names = layout.of_kind("integer")
        optional = set(layout.appended)
        text = []
        integer = []
        real_rows = []
        for i, row in enumerate(rows):
            for name, value in fixed.items():
                if row.get(name, value) != value:
                    raise RecordError(f"{table} row {i}: {name} {row[name]!r} is not {value!r}")
            try:
                text.append(
                    tuple(
                        as_text(
                            fixed[n] if n in fixed else row.get(n) if n in optional else row[n],
                            f"{table}.{n}",
                        )
                        for n in text_names
                    )
                )
                integer.append(tuple(as_int(row[n], f"{table}.{n}") for n in int_names))
                real_rows.append([row.get(n) if n in optional else row[n] for n in real_names])
            except KeyError as missing:
                raise RecordError(f"{table} row {i} has no column {missing}") from None
        return cls(layout, text, _real_matrix(layout, real_rows, real_names), integer)

    @classmethod
    def from_columns(
        cls, layout: TableLayout, columns: Columnar, fixed: Mapping[str, str] | None = None
    ) -> RowBatch:
        """Rows as columns (name → sequence/array); ``fixed`` columns as in
        :meth:`from_mappings`."""
        fixed = fixed or {}
        table = layout.name
        _check_names(layout, columns.keys(), fixed)
        lengths = {len(columns[n]) for n in layout.names if n in columns}
        if len(lengths) > 1:
            raise RecordError(f"{table} columns differ in length: {sorted(lengths)}")
        n = lengths.pop() if lengths else 0
        text_cols: list[list[str | None]] = []
        for name in layout.of_kind("text"):
            if name in fixed:
                given = columns.get(name)
                if given is not None and any(v != fixed[name] for v in given):
                    raise RecordError(f"{table}.{name}: every value must be {fixed[name]!r}")
                text_cols.append([fixed[name]] * n)
            elif name not in columns and name in layout.appended:
                text_cols.append([None] * n)
            else:
                text_cols.append([as_text(v, f"{table}.{name}") for v in columns[name]])
        int_cols = [
            [as_int(v, f"{table}.{name}") for v in _python_values(columns[name])]
            for name in layout.of_kind("integer")
        ]
        real_names = layout.of_kind("real")
        absent = np.full(n, np.nan)
        try:
            real = (
                np.array(
                    [
                        columns[c] if c in columns or c not in layout.appended else absent
                        for c in real_names
                    ],
                    dtype=np.float64,
                ).T
                if real_names
                else np.zeros((n, 0))
            )
        except (TypeError, ValueError) as error:
            raise RecordError(f"{table}: a real column holds a non-number ({error})") from None
        return cls(
            layout,
            list(zip(*text_cols, strict=True)) if text_cols else [()] * n,
            real.reshape(n, len(real_names)),
            list(zip(*int_cols, strict=True)) if int_cols else [()] * n,
        )

    @classmethod
    def from_grouped(cls, layout: TableLayout, rows: Sequence[Sequence[Any]]) -> RowBatch:
        """Rows whose values are already in grouped order and type (as SQLite returns
        them for ``SELECT <grouped columns>``, or as parsed from CSV cells)."""
        n_text = len(layout.of_kind("text"))
        n_real = len(layout.of_kind("real"))
        text = [tuple(row[:n_text]) for row in rows]
        real_rows = [row[n_text : n_text + n_real] for row in rows]
        integer = [tuple(row[n_text + n_real :]) for row in rows]
        return cls(layout, text, _real_matrix(layout, real_rows, layout.of_kind("real")), integer)

    def checksums(self) -> list[str]:
        """Each row's content checksum (see :mod:`workcell.record.checksum`)."""
        n, k = len(self), len(self.layout.of_kind("integer"))
        null = np.array([[v is None for v in row] for row in self.integer], dtype=np.bool_)
        ints = np.array([[v or 0 for v in row] for row in self.integer], dtype=np.int64)
        return row_checksums(
            self.layout.name,
            self.text,
            self.real,
            ints.reshape(n, k),
            null.reshape(n, k),
            appended=self.layout.appended_counts,
        )

    def sql_rows(self, checksums: Sequence[str]) -> list[tuple[object, ...]]:
        """Parameters for ``INSERT INTO t (<grouped columns>, checksum)``."""
        return [
            (*text, *real, *ints, checksum)
            for text, real, ints, checksum in zip(
                self.text, self.real.tolist(), self.integer, checksums, strict=True
            )
        ]

    def to_columns(self) -> dict[str, NDArray[Any]]:
        """Columns in table order: text as object arrays (None for NULL), real as float64
        (NaN for NULL), integer as int64, or as float64 with NaN where NULL is legitimate."""
        layout = self.layout
        out: dict[str, NDArray[Any]] = {}
        for j, name in enumerate(layout.of_kind("text")):
            column = np.empty(len(self), dtype=object)
            column[:] = [row[j] for row in self.text]
            out[name] = column
        for j, name in enumerate(layout.of_kind("real")):
            out[name] = self.real[:, j].copy()
        for j, name in enumerate(layout.of_kind("integer")):
            values = [row[j] for row in self.integer]
            if layout.column(name).nullable:
                out[name] = np.array(values, dtype=np.float64).reshape(len(self))
            elif None in values:
                raise RecordError(
                    f"{layout.name}.{name} holds NULL in {values.count(None)} rows; "
                    "run 'workcell verify' on the store"
                )
            else:
                out[name] = np.array(values, dtype=np.int64).reshape(len(self))
        return {name: out[name] for name in layout.names}


def _check_names(layout: TableLayout, given: Any, fixed: Mapping[str, str]) -> None:
    names = set(given)
    optional = set(layout.appended)  # columns a later version added may be left out
    missing = [n for n in layout.names if n not in names and n not in fixed and n not in optional]
    unknown = sorted(names - set(layout.names))
    problems = []
    if missing:
        problems.append(f"missing {', '.join(missing)}")
    if unknown:
        problems.append(f"unknown {', '.join(unknown)}")
    if problems:
        raise RecordError(
            f"{layout.name} columns: {'; '.join(problems)} "
            f"(the columns are those of workcell.record.columns)"
        )


def _python_values(values: Any) -> list[object]:
    return values.tolist() if isinstance(values, np.ndarray) else list(values)


def _real_matrix(
    layout: TableLayout, rows: Sequence[Sequence[Any]], names: tuple[str, ...]
) -> NDArray[np.float64]:
    try:
        real = np.array(rows, dtype=np.float64)
    except (TypeError, ValueError):
        for row in rows:
            for name, value in zip(names, row, strict=True):
                if value is not None and not isinstance(value, int | float | np.number):
                    raise RecordError(
                        f"{layout.name}.{name}: expected a number, "
                        f"got {type(value).__name__} {value!r}"
                    ) from None
        raise
    return real.reshape(len(rows), len(names))


def frames_from_columns(
    columns: Columnar, session_id: str, trial_id: str, first_index: int = 0
) -> RowBatch:
    """Frames given as columns (every frame column but the ids) as the batch
    :meth:`Store.add_frames <workcell.record.store.Store.add_frames>` takes: ``session_id``
    and ``trial_id`` filled in, ``frame_index`` counting from ``first_index`` where it is
    left out."""
    if "frame_index" not in columns and columns:
        n = len(next(iter(columns.values())))
        columns = {**columns, "frame_index": range(first_index, first_index + n)}
    return RowBatch.from_columns(FRAMES, columns, {"session_id": session_id, "trial_id": trial_id})

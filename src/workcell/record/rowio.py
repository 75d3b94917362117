"""Reading and writing whole rows of any table, each with its checksum kept current."""

from __future__ import annotations

import sqlite3
from collections.abc import Iterator, Mapping, Sequence
from functools import cache
from typing import Any

from workcell.record.batch import RowBatch
from workcell.record.layout import CHECKSUM, TableLayout
from workcell.record.schema import column_list, quote

FETCH_ROWS = 1024


@cache
def insert_sql(layout: TableLayout) -> str:
    names = (*layout.grouped, CHECKSUM)
    marks = ", ".join("?" * len(names))
    return f"INSERT INTO {quote(layout.name)} ({column_list(names)}) VALUES ({marks})"


def insert(conn: sqlite3.Connection, batch: RowBatch) -> None:
    """Insert every row of ``batch`` with its checksum (inside the caller's transaction)."""
    conn.executemany(insert_sql(batch.layout), batch.sql_rows(batch.checksums()))


def insert_one(conn: sqlite3.Connection, layout: TableLayout, row: Mapping[str, object]) -> None:
    insert(conn, RowBatch.from_mappings(layout, [row]))


def select(
    conn: sqlite3.Connection,
    layout: TableLayout,
    where: str = "",
    params: Sequence[object] = (),
    order: str = "",
) -> list[dict[str, Any]]:
    """Rows of ``layout`` as dicts in table order (``where``/``order`` are SQL fragments)."""
    sql = f"SELECT {column_list(layout.names)} FROM {quote(layout.name)}"
    sql += f" WHERE {where}" if where else ""
    sql += f" ORDER BY {order}" if order else ""
    return [dict(zip(layout.names, row, strict=True)) for row in conn.execute(sql, params)]


def select_grouped(
    conn: sqlite3.Connection,
    layout: TableLayout,
    where: str = "",
    params: Sequence[object] = (),
    order: str = "",
) -> Iterator[tuple[RowBatch, list[str], list[Any]]]:
    """Rows of ``layout`` in chunks: the batch, the stored checksums and the table keys.

    Streams (at most :data:`FETCH_ROWS` rows in memory), for verification and export.
    """
    key = column_list(layout.key)
    sql = f"SELECT {column_list((*layout.grouped, CHECKSUM))}, {key} FROM {quote(layout.name)}"
    sql += f" WHERE {where}" if where else ""
    sql += f" ORDER BY {order}" if order else ""
    cursor = conn.execute(sql, params)
    n = len(layout.grouped)
    while rows := cursor.fetchmany(FETCH_ROWS):
        batch = RowBatch.from_grouped(layout, [row[:n] for row in rows])
        keys = [row[n + 1 :] if len(layout.key) > 1 else row[n + 1] for row in rows]
        yield batch, [row[n] for row in rows], keys


def update(
    conn: sqlite3.Connection,
    layout: TableLayout,
    key: Mapping[str, object],
    changes: Mapping[str, object],
) -> None:
    """Change some columns of one row and recompute its checksum (in the caller's
    transaction). Key columns are never changed, so no foreign-key scan runs."""
    where = " AND ".join(f"{quote(name)} = ?" for name in key)
    rows = select(conn, layout, where, tuple(key.values()))
    if len(rows) != 1:
        raise KeyError(f"{layout.name} row {dict(key)} not found")
    row = rows[0] | dict(changes)
    batch = RowBatch.from_mappings(layout, [row])
    checksum = batch.checksums()[0]
    # the values as stored (empty text as NULL, integers checked)
    stored = dict(zip(layout.grouped, batch.sql_rows([checksum])[0], strict=False))
    names = [name for name in layout.grouped if name in changes]
    assignments = ", ".join(f"{quote(name)} = ?" for name in (*names, CHECKSUM))
    conn.execute(
        f"UPDATE {quote(layout.name)} SET {assignments} WHERE {where}",
        (*(stored[name] for name in names), checksum, *key.values()),
    )

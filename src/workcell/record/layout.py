"""How a store's table is laid out: its columns, their SQL kinds and which may be NULL, its
key, and the columns later schema versions appended. :mod:`workcell.record.schema` declares
the tables with these."""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from typing import Literal

CHECKSUM = "checksum"
"""Every row table's last column (but for appended columns): sha256 (hex) of the row's
canonical serialization."""

Kind = Literal["text", "integer", "real"]


@dataclass(frozen=True)
class Column:
    """``not_null``: SQL refuses NULL. ``nullable``: NULL is a legitimate value (verify
    accepts it; columnar reads give NaN or None); otherwise NULL marks a fault."""

    name: str
    kind: Kind
    not_null: bool = False
    nullable: bool = True


@dataclass(frozen=True)
class Appended:
    """Text and real columns one later schema ``version`` added to a table, in table order."""

    version: int
    names: tuple[str, ...]


@dataclass(frozen=True, eq=False)
class TableLayout:
    """One table: its columns in table order, its primary key and its row-checksum column.

    ``added`` holds the columns later schema versions added, oldest first: the last
    columns, stored after ``checksum``, text or real (so that they are the last of their
    kind too), and each version's hashed into a row's checksum only where the row holds
    one of them (:func:`~workcell.record.checksum.row_checksums`), so the rows written
    before they existed keep their checksums."""

    name: str
    columns: tuple[Column, ...]
    key: tuple[str, ...]
    constraints: tuple[str, ...] = ()
    added: tuple[Appended, ...] = ()

    def __post_init__(self) -> None:
        tail = tuple(c.name for c in self.columns[len(self.columns) - len(self.appended) :])
        if self.appended and (
            tail != self.appended or any(self.column(n).kind == "integer" for n in tail)
        ):
            raise ValueError(
                f"{self.name}: appended columns must be the last columns, text or real"
            )

    @cached_property
    def appended(self) -> tuple[str, ...]:
        """The names of every column a later schema version added, in table order."""
        return tuple(name for group in self.added for name in group.names)

    @cached_property
    def appended_counts(self) -> tuple[tuple[int, int, int], ...]:
        """Per version that added columns (oldest first): (version, how many text, how
        many real columns), as :func:`~workcell.record.checksum.row_checksums` takes them."""
        return tuple(
            (
                group.version,
                sum(self.column(n).kind == "text" for n in group.names),
                sum(self.column(n).kind == "real" for n in group.names),
            )
            for group in self.added
        )

    @cached_property
    def names(self) -> tuple[str, ...]:
        """Column names in table order, without the ``checksum`` column."""
        return tuple(c.name for c in self.columns)

    @cached_property
    def stored(self) -> tuple[tuple[str, Kind], ...]:
        """(name, kind) of every column as the table stores them: the columns, the
        ``checksum`` column, then the appended columns."""
        first = len(self.columns) - len(self.appended)
        return (
            *((c.name, c.kind) for c in self.columns[:first]),
            (CHECKSUM, "text"),
            *((c.name, c.kind) for c in self.columns[first:]),
        )

    def of_kind(self, kind: Kind) -> tuple[str, ...]:
        return self._kinds[kind]

    @cached_property
    def _kinds(self) -> dict[Kind, tuple[str, ...]]:
        kinds: tuple[Kind, ...] = ("text", "real", "integer")
        return {k: tuple(c.name for c in self.columns if c.kind == k) for k in kinds}

    @cached_property
    def grouped(self) -> tuple[str, ...]:
        """Text, then real, then integer columns (each in table order): the order in which
        rows are serialized for checksums and passed to SQL by
        :class:`~workcell.record.batch.RowBatch`."""
        return self.of_kind("text") + self.of_kind("real") + self.of_kind("integer")

    def column(self, name: str) -> Column:
        return self._by_name[name]

    @cached_property
    def _by_name(self) -> dict[str, Column]:
        return {c.name: c for c in self.columns}


def kinds_of(kind: Kind, names: tuple[str, ...]) -> dict[str, Kind]:
    return dict.fromkeys(names, kind)


def columns_of(
    names: tuple[str, ...],
    kinds: dict[str, Kind],
    not_null: set[str],
    nullable: set[str] | None = None,
) -> tuple[Column, ...]:
    """Columns of ``names``: real unless ``kinds`` says otherwise; NULL is legitimate in
    ``nullable`` (default: every column SQL allows NULL in)."""
    return tuple(
        Column(
            n,
            kinds.get(n, "real"),
            not_null=n in not_null,
            nullable=(n not in not_null) if nullable is None else n in nullable,
        )
        for n in names
    )

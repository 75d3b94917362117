"""Schema version 6 of a store: the five tables, their column types, and the DDL.

Every table's columns are the interchange contract's names (:mod:`workcell.record.columns`)
followed by the store's own (``checksum``, ``content_checksum``, ...). The version lives in
``PRAGMA user_version`` and in the ``meta`` table; ``PRAGMA application_id`` marks the file
as a Workcell store. Tables are STRICT, so a column holds only its declared type.

Version 2 added the ``chain`` table (:mod:`workcell.record.chain`); version 3 the frames'
filtered device poses (:data:`~workcell.record.columns.FILTERED_POSE_COLUMNS`), appended
after the ``checksum`` column as ``ALTER TABLE`` appends them, so that a new store and a
migrated one have the same tables; version 4 the store's identity in its chains (the
``chain_roots`` table) and the chain tip kept in ``meta``; version 5 the task-neutral columns
(:data:`~workcell.record.columns.TRIAL_TASK_COLUMNS` of the trials,
:data:`~workcell.record.columns.FRAME_TASK_COLUMNS` of the frames), appended the same way;
version 6 who drove (the trials' ``driver``, the frames' ``intervention``), appended the
same way. A writer migrates an older store (:mod:`workcell.record.migrate`).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from typing import Literal

from workcell.record.columns import (
    ANNOTATION_COLUMNS,
    EVENT_COLUMNS,
    FILTERED_POSE_COLUMNS,
    FRAME_COLUMNS,
    FRAME_DEVICE_COLUMNS,
    FRAME_INTERVENTION_COLUMNS,
    FRAME_TASK_COLUMNS,
    SESSION_COLUMNS,
    TRIAL_COLUMNS,
    TRIAL_DRIVER_COLUMNS,
    TRIAL_TASK_COLUMNS,
)

SCHEMA_VERSION = 6
APPLICATION_ID = 0x57434C31
"""``PRAGMA application_id`` of every Workcell store: ASCII "WCL1"."""

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
        rows are serialized for checksums and passed to SQL by :class:`RowBatch`."""
        return self.of_kind("text") + self.of_kind("real") + self.of_kind("integer")

    def column(self, name: str) -> Column:
        return self._by_name[name]

    @cached_property
    def _by_name(self) -> dict[str, Column]:
        return {c.name: c for c in self.columns}


def _of(kind: Kind, names: tuple[str, ...]) -> dict[str, Kind]:
    return dict.fromkeys(names, kind)


def _columns(
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


FRAME_INTEGER_COLUMNS: tuple[str, ...] = (
    "frame_index",
    "follow_l",
    "follow_r",
    "buttons_l",
    "buttons_r",
    "contact_l",
    "contact_r",
    "attached",
)
FRAMES = TableLayout(
    "frames",
    _columns(
        FRAME_COLUMNS,
        _of("text", ("session_id", "trial_id", "boxes", "stage"))
        | _of("integer", FRAME_INTEGER_COLUMNS),
        # Measured values may be NULL in SQL so that a NaN (stored as NULL by SQLite) never
        # costs a frame; `workcell verify` reports NULLs outside the device columns (and
        # the task columns, NULL in frames recorded before version 5).
        {"session_id", "trial_id", "frame_index", "boxes"},
        set(FRAME_DEVICE_COLUMNS) | set(FRAME_TASK_COLUMNS) | set(FRAME_INTERVENTION_COLUMNS),
    ),
    key=("trial_id", "frame_index"),
    constraints=("FOREIGN KEY (session_id, trial_id) REFERENCES trials (session_id, trial_id)",),
    added=(
        Appended(3, FILTERED_POSE_COLUMNS),
        Appended(5, FRAME_TASK_COLUMNS),
        Appended(6, FRAME_INTERVENTION_COLUMNS),
    ),
)

TRIAL_EXTRA_COLUMNS: tuple[str, ...] = (
    "trial_seed",
    "started_wall",
    "ended_wall",
    "content_checksum",
)
TRIALS = TableLayout(
    "trials",
    _columns(
        TRIAL_COLUMNS + TRIAL_EXTRA_COLUMNS + TRIAL_TASK_COLUMNS + TRIAL_DRIVER_COLUMNS,
        _of(
            "text",
            (
                "driver",
                "task",
                "world",
                "stage",
                "goal_json",
                "session_id",
                "trial_id",
                "mode",
                "outcome",
                "interruption_reason",
                "quality_flags",
                "exclusion_reason",
                "content_checksum",
            ),
        )
        | _of(
            "integer",
            (
                "trial_index",
                "round",
                "level",
                "required_boxes",
                "boxes_delivered",
                "score",
                "n_frames",
                "included",
                "trial_seed",
            ),
        ),
        {
            "session_id",
            "trial_id",
            "trial_index",
            "mode",
            "required_boxes",
            "time_limit_s",
            "started_wall",
        },
    ),
    key=("trial_id",),
    constraints=(
        "UNIQUE (session_id, trial_id)",
        "UNIQUE (session_id, trial_index)",
        "FOREIGN KEY (session_id) REFERENCES sessions (session_id)",
    ),
    added=(Appended(5, TRIAL_TASK_COLUMNS), Appended(6, TRIAL_DRIVER_COLUMNS)),
)

SESSIONS = TableLayout(
    "sessions",
    _columns(
        (*SESSION_COLUMNS, "content_checksum"),
        _of(
            "text",
            (
                *(n for n in SESSION_COLUMNS if n.endswith("_json")),
                "session_id",
                "software_version",
                "mode",
                "operator_id",
                "metrics_version",
                "status",
                "content_checksum",
            ),
        )
        | {"schema_version": "integer", "seed": "integer"},
        set(SESSION_COLUMNS) - {"ended_wall"},
    ),
    key=("session_id",),
)

EVENTS = TableLayout(
    "events",
    _columns(
        EVENT_COLUMNS,
        _of("text", ("event_id", "session_id", "trial_id", "kind", "payload_json"))
        | {"seq": "integer"},
        {"event_id", "session_id", "seq", "t_wall", "kind", "payload_json"},
    ),
    key=("event_id",),
    constraints=(
        "UNIQUE (session_id, seq)",
        "FOREIGN KEY (session_id) REFERENCES sessions (session_id)",
        "FOREIGN KEY (session_id, trial_id) REFERENCES trials (session_id, trial_id)",
    ),
)

ANNOTATIONS = TableLayout(
    "annotations",
    _columns(
        ANNOTATION_COLUMNS,
        _of("text", ("annotation_id", "trial_id", "kind", "reason", "by")),
        set(ANNOTATION_COLUMNS),
    ),
    key=("annotation_id",),
    constraints=("FOREIGN KEY (trial_id) REFERENCES trials (trial_id)",),
)

LAYOUTS: tuple[TableLayout, ...] = (SESSIONS, TRIALS, EVENTS, FRAMES, ANNOTATIONS)
"""Every row table, parents before children."""

CHECKSUM = "checksum"
"""Every row table's last column (but for appended columns): sha256 (hex) of the row's
canonical serialization."""

INDEXES: tuple[str, ...] = (
    "CREATE INDEX events_by_trial ON events (trial_id, seq)",
    "CREATE INDEX annotations_by_trial ON annotations (trial_id)",
)


def quote(name: str) -> str:
    """An SQL identifier in double quotes (column names like ``by`` are keywords)."""
    return '"' + name.replace('"', '""') + '"'


def column_list(names: tuple[str, ...]) -> str:
    return ", ".join(quote(n) for n in names)


def create_table_sql(layout: TableLayout) -> str:
    def definition(name: str) -> str:
        if name == CHECKSUM:
            return f"{quote(CHECKSUM)} TEXT NOT NULL"
        c = layout.column(name)
        return f"{quote(c.name)} {c.kind.upper()}{' NOT NULL' if c.not_null else ''}"

    lines = [definition(name) for name, _ in layout.stored]  # checksum, appended in place
    lines.append(f"PRIMARY KEY ({column_list(layout.key)})")
    lines.extend(layout.constraints)
    body = ",\n    ".join(lines)
    return f"CREATE TABLE {quote(layout.name)} (\n    {body}\n) STRICT"


META_TABLE_SQL = "CREATE TABLE meta (key TEXT NOT NULL PRIMARY KEY, value TEXT NOT NULL) STRICT"


FRAME_BLOCKS_SQL = """CREATE TABLE IF NOT EXISTS frame_blocks (
    trial_id TEXT PRIMARY KEY REFERENCES trials (trial_id),
    n_frames INTEGER NOT NULL,
    columns TEXT NOT NULL,
    data BLOB NOT NULL,
    checksum TEXT NOT NULL
) STRICT"""
"""Per-trial frame blocks (:mod:`workcell.record.frame_blocks`); a store written before
they existed gets the table when a writer opens it."""


CHAIN_SQL = """CREATE TABLE chain (
    session_id TEXT NOT NULL REFERENCES sessions (session_id),
    position INTEGER NOT NULL,
    kind TEXT NOT NULL,
    subject_id TEXT NOT NULL,
    events_through INTEGER NOT NULL,
    previous TEXT NOT NULL,
    digest TEXT NOT NULL,
    head TEXT NOT NULL,
    key_id TEXT,
    signature TEXT,
    created_wall REAL NOT NULL,
    PRIMARY KEY (session_id, position)
) STRICT"""
"""The hash chain (:mod:`workcell.record.chain`), one row per link (since version 2):
``events_through`` says which session-level events (``trial_id`` NULL, ``seq`` up to it)
this link or one before it commits to (-1: none)."""

CHAIN_ROOTS_SQL = """CREATE TABLE chain_roots (
    root TEXT NOT NULL PRIMARY KEY,
    store_id TEXT NOT NULL,
    joined TEXT NOT NULL,
    joined_wall REAL NOT NULL
) STRICT"""
"""The points the chains of a store may start from (:mod:`workcell.record.chain_tip`,
since version 4): this store's own root, the roots of the stores merged into it and, in a
store migrated from an older version, the empty root its first chains started from."""


def schema_statements() -> tuple[str, ...]:
    """Every statement that creates an empty store (run in one transaction)."""
    return (
        META_TABLE_SQL,
        *(create_table_sql(layout) for layout in LAYOUTS),
        *INDEXES,
        FRAME_BLOCKS_SQL,
        CHAIN_SQL,
        CHAIN_ROOTS_SQL,
        f"PRAGMA application_id = {APPLICATION_ID}",
        f"PRAGMA user_version = {SCHEMA_VERSION}",
    )

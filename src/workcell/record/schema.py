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
from workcell.record.layout import CHECKSUM, Appended, TableLayout, columns_of, kinds_of

SCHEMA_VERSION = 6
APPLICATION_ID = 0x57434C31
"""``PRAGMA application_id`` of every Workcell store: ASCII "WCL1"."""

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
    columns_of(
        FRAME_COLUMNS,
        kinds_of("text", ("session_id", "trial_id", "boxes", "stage"))
        | kinds_of("integer", FRAME_INTEGER_COLUMNS),
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
    columns_of(
        TRIAL_COLUMNS + TRIAL_EXTRA_COLUMNS + TRIAL_TASK_COLUMNS + TRIAL_DRIVER_COLUMNS,
        kinds_of(
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
        | kinds_of(
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
    columns_of(
        (*SESSION_COLUMNS, "content_checksum"),
        kinds_of(
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
    columns_of(
        EVENT_COLUMNS,
        kinds_of("text", ("event_id", "session_id", "trial_id", "kind", "payload_json"))
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
    columns_of(
        ANNOTATION_COLUMNS,
        kinds_of("text", ("annotation_id", "trial_id", "kind", "reason", "by")),
        set(ANNOTATION_COLUMNS),
    ),
    key=("annotation_id",),
    constraints=("FOREIGN KEY (trial_id) REFERENCES trials (trial_id)",),
)

LAYOUTS: tuple[TableLayout, ...] = (SESSIONS, TRIALS, EVENTS, FRAMES, ANNOTATIONS)
"""Every row table, parents before children."""

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

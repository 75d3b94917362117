"""Frame blocks: per trial, the frame columns the metrics read, stored column by column.

The frame rows stay the record; a block is an index of them for fast reading. When a
trial closes, the store writes its block from the frames as stored: the
:data:`BLOCK_COLUMNS` of every frame, float64 little-endian, one column after another,
with NULL as NaN and -0.0 as 0.0 (exactly what reading the rows back gives).
``workcell verify`` checks every block against its trial's frames; an audit reads blocks
where they agree with the trial row's frame count and the frame rows elsewhere.
"""

from __future__ import annotations

import hashlib
import sqlite3

import numpy as np
from numpy.typing import NDArray

from workcell.metrics.frames import REQUIRED_COLUMNS
from workcell.record.checksum import canonical_reals
from workcell.record.schema import FRAMES

BLOCK_COLUMNS: tuple[str, ...] = REQUIRED_COLUMNS
"""The frame columns a block holds, in order: those the metrics and detectors use."""
COLUMNS_TEXT = ",".join(BLOCK_COLUMNS)

BLOCK_REALS = np.array([FRAMES.of_kind("real").index(name) for name in BLOCK_COLUMNS])
"""Where the block's columns are among the real columns of a frames batch."""


def block_data(matrix: NDArray[np.float64]) -> bytes:
    """The stored form of an (n, len(BLOCK_COLUMNS)) matrix: column after column."""
    return canonical_reals(np.asarray(matrix, dtype=np.float64).T).tobytes()


def block_checksum(trial_id: str, n_frames: int, columns: str, data: bytes) -> str:
    h = hashlib.sha256(b"workcell/frame_blocks/v1\0")
    h.update(f"{trial_id}\0{n_frames}\0{columns}\0".encode())
    h.update(data)
    return h.hexdigest()


def write_block(conn: sqlite3.Connection, trial_id: str, matrix: NDArray[np.float64]) -> None:
    """Store the block of a trial (inside the caller's transaction)."""
    data = block_data(matrix)
    n = len(matrix)
    conn.execute(
        "INSERT INTO frame_blocks (trial_id, n_frames, columns, data, checksum) "
        "VALUES (?, ?, ?, ?, ?)",
        (trial_id, n, COLUMNS_TEXT, data, block_checksum(trial_id, n, COLUMNS_TEXT, data)),
    )


def has_blocks(conn: sqlite3.Connection, schema: str = "main") -> bool:
    """Whether the database (``schema``: main, or an attached one) has frame blocks."""
    row = conn.execute(
        f"SELECT 1 FROM {schema}.sqlite_schema WHERE type = 'table' AND name = 'frame_blocks'"
    ).fetchone()
    return row is not None


def read_block(
    conn: sqlite3.Connection, trial_id: str, n_frames: int
) -> NDArray[np.float64] | None:
    """The (n_frames, len(BLOCK_COLUMNS)) block of a trial, a read-only view; None when
    there is none of ``n_frames`` frames and these columns."""
    row = conn.execute(
        "SELECT n_frames, columns, data FROM frame_blocks WHERE trial_id = ?", (trial_id,)
    ).fetchone()
    if row is None or row[0] != n_frames or row[1] != COLUMNS_TEXT:
        return None
    data = row[2]
    if len(data) != 8 * n_frames * len(BLOCK_COLUMNS):
        return None
    return np.frombuffer(data, dtype="<f8").reshape(len(BLOCK_COLUMNS), n_frames).T


def block_problems(
    conn: sqlite3.Connection, trial_id: str, matrix: NDArray[np.float64]
) -> list[str]:
    """What is wrong with the trial's block, given its frames' BLOCK_COLUMNS as read from
    the rows (none when it has no block)."""
    row = conn.execute(
        "SELECT n_frames, columns, data, checksum FROM frame_blocks WHERE trial_id = ?",
        (trial_id,),
    ).fetchone()
    if row is None:
        return []
    n, columns, data, checksum = row
    problems = []
    if checksum != block_checksum(trial_id, n, columns, data):
        problems.append("checksum mismatch: the block was changed after it was written")
    if columns != COLUMNS_TEXT:
        problems.append(f"holds columns {columns!r}, expected {COLUMNS_TEXT!r}")
    elif n != len(matrix) or data != block_data(matrix):
        problems.append("differs from the trial's frames")
    return problems

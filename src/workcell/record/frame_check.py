"""Verifying one trial's frames, streamed: checksums, indices, clocks and finite values."""

from __future__ import annotations

import sqlite3
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from workcell.record import rowio
from workcell.record.findings import frames_label
from workcell.record.frame_blocks import BLOCK_REALS, block_problems, has_blocks
from workcell.record.schema import FRAMES

Report = Callable[[str, str, str], None]
"""``report(table, row, problem)``."""

_REAL = FRAMES.of_kind("real")
_INTEGER = FRAMES.of_kind("integer")
_T_SIM, _T_WALL = _REAL.index("t_sim"), _REAL.index("t_wall")
_INDEX = _INTEGER.index("frame_index")
_REAL_NULLABLE = np.array([FRAMES.column(c).nullable for c in _REAL], dtype=bool)
_INTEGER_NULLABLE = [FRAMES.column(c).nullable for c in _INTEGER]


@dataclass
class _Problems:
    """Frame indices per problem, in the order found."""

    by_problem: dict[str, list[int]] = field(default_factory=dict)

    def add(self, problem: str, indices: list[int]) -> None:
        if indices:
            self.by_problem.setdefault(problem, []).extend(indices)


def check_trial_frames(conn: sqlite3.Connection, trial_id: str, report: Report) -> int:
    """Check the trial's frames in frame_index order, and its frame block against them;
    report problems, each naming the frames it concerns; return how many frames are
    stored."""
    problems = _Problems()
    block_columns: list[NDArray[np.float64]] = []
    count = 0
    last_sim, last_wall = -np.inf, -np.inf
    for batch, stored, keys in rowio.select_grouped(
        conn, FRAMES, "trial_id = ?", (trial_id,), "frame_index"
    ):
        indices = [key[1] for key in keys]
        sums = batch.checksums()
        problems.add(
            "checksum mismatch: the frame was changed after it was written",
            [i for i, a, b in zip(indices, stored, sums, strict=True) if a != b],
        )
        expected = np.arange(count, count + len(batch))
        problems.add(
            "frame_index out of sequence: frames are missing",
            [i for i, e in zip(indices, expected, strict=True) if i != e][:1],
        )
        count += len(batch)

        real = batch.real
        block_columns.append(real[:, BLOCK_REALS])
        t_sim = np.concatenate([[last_sim], real[:, _T_SIM]])
        t_wall = np.concatenate([[last_wall], real[:, _T_WALL]])
        problems.add(
            "t_sim does not increase",
            [indices[k] for k in np.flatnonzero(~(t_sim[1:] > t_sim[:-1]))],
        )
        problems.add(
            "t_wall goes back in time",
            [indices[k] for k in np.flatnonzero(t_wall[1:] < t_wall[:-1])],
        )
        last_sim, last_wall = float(real[-1, _T_SIM]), float(real[-1, _T_WALL])

        infinite = np.isinf(real)
        null = np.isnan(real) & ~_REAL_NULLABLE
        for col in np.flatnonzero(infinite.any(axis=0)):
            problems.add(
                f"{_REAL[col]} is infinite",
                [indices[i] for i in np.flatnonzero(infinite[:, col])],
            )
        for col in np.flatnonzero(null.any(axis=0)):
            problems.add(
                f"{_REAL[col]} is NULL or NaN (only device columns may be)",
                [indices[i] for i in np.flatnonzero(null[:, col])],
            )
        for j, name in enumerate(_INTEGER):
            if not _INTEGER_NULLABLE[j]:
                problems.add(
                    f"{name} is NULL (only device columns may be)",
                    [i for i, row in zip(indices, batch.integer, strict=True) if row[j] is None],
                )
    for problem, where in problems.by_problem.items():
        report("frames", frames_label(trial_id, where), problem)
    if has_blocks(conn):
        matrix = np.concatenate(block_columns) if block_columns else np.zeros((0, len(BLOCK_REALS)))
        for problem in block_problems(conn, trial_id, matrix):
            report("frame_blocks", f"trial {trial_id}", problem)
    return count

"""Hand-built frames for the metric tests: every required column zero unless given."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import numpy.typing as npt

from workcell.metrics import REQUIRED_COLUMNS, FrameArrays

Columns = dict[str, npt.NDArray[np.float64]]
Values = Sequence[float] | npt.NDArray[np.float64]


def columns(n: int, **given: Values) -> Columns:
    """frames.csv columns of an n-frame trial at 20 Hz: ``t_sim`` = 0, 0.05, ..,
    ``t_wall`` = 1000 s + the same, every other required column 0; ``given`` overrides."""
    cols: Columns = {name: np.zeros(n) for name in REQUIRED_COLUMNS}
    cols["t_sim"] = np.arange(n, dtype=np.float64) * 0.05
    cols["t_wall"] = 1000.0 + np.arange(n, dtype=np.float64) * 0.05
    for name, values in given.items():
        assert name in cols, f"{name} is not a required column"
        assert len(values) == n, f"{name} has {len(values)} values, not {n}"
        cols[name] = np.asarray(values, dtype=np.float64)
    return cols


def frames(n: int, **given: Values) -> FrameArrays:
    """:func:`columns` as :class:`FrameArrays`."""
    return FrameArrays.from_columns(columns(n, **given))


def positions(prefix: str, points: Sequence[tuple[float, float, float]]) -> Columns:
    """``<prefix>_x/y/z`` columns from a list of (x, y, z) points in metres."""
    xyz = np.asarray(points, dtype=np.float64)
    return {f"{prefix}_{axis}": xyz[:, i] for i, axis in enumerate("xyz")}

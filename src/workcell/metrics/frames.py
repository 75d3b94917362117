"""One trial's frames as the numpy arrays the metrics read.

Units follow the interchange contract: seconds (``t_sim`` from trial start, ``t_wall`` Unix
time), metres and m/s for positions and base velocity, rad and rad/s for yaw rate and arm
joints, grip button values 0-1. Arrays are float64 and read-only.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, fields
from typing import Any

import numpy as np
import numpy.typing as npt

from workcell.errors import MetricsError
from workcell.sim.joints import arm_joint_names

FloatArray = npt.NDArray[np.float64]
Column = npt.NDArray[Any] | Sequence[float]

_GROUPS: dict[str, tuple[str, ...]] = {
    "t_sim": ("t_sim",),
    "t_wall": ("t_wall",),
    "base_v": ("base_vx", "base_vy", "base_wz"),
    "tcp_l": ("tcp_l_x", "tcp_l_y", "tcp_l_z"),
    "tcp_r": ("tcp_r_x", "tcp_r_y", "tcp_r_z"),
    "q_l": tuple(f"q_{j}" for j in arm_joint_names("l")),
    "q_r": tuple(f"q_{j}" for j in arm_joint_names("r")),
    "dq_l": tuple(f"dq_{j}" for j in arm_joint_names("l")),
    "dq_r": tuple(f"dq_{j}" for j in arm_joint_names("r")),
    "grip_l": ("grip_l",),
    "grip_r": ("grip_r",),
}
"""FrameArrays field -> the frames.csv columns it holds, in order (1 column: shape (n,))."""

REQUIRED_COLUMNS: tuple[str, ...] = tuple(c for cols in _GROUPS.values() for c in cols)
"""The frames.csv columns the metrics need."""


@dataclass(frozen=True)
class FrameArrays:
    """One trial's frames, n of them, in recording order.

    ``t_sim``, ``t_wall`` (s), ``grip_l``, ``grip_r`` (0-1) have shape (n,); ``base_v``
    (n, 3) holds vx, vy (m/s, world frame) and wz (rad/s); ``tcp_l``, ``tcp_r`` (n, 3) the
    TCP positions (m, world frame); ``q_l``, ``q_r`` (n, 7) arm joint positions (rad) and
    ``dq_l``, ``dq_r`` (n, 7) their rates (rad/s), shoulder to wrist. Fields are read-only
    float64 views; :meth:`from_columns` copies the columns it is given and lays (n, k)
    blocks out column-major (fastest).
    """

    t_sim: FloatArray
    t_wall: FloatArray
    base_v: FloatArray
    tcp_l: FloatArray
    tcp_r: FloatArray
    q_l: FloatArray
    q_r: FloatArray
    dq_l: FloatArray
    dq_r: FloatArray
    grip_l: FloatArray
    grip_r: FloatArray

    def __post_init__(self) -> None:
        t_sim_shape = np.shape(self.t_sim)
        n = t_sim_shape[0] if t_sim_shape else -1
        problems = []
        for f in fields(self):
            array = np.asarray(getattr(self, f.name), dtype=np.float64).view()
            array.flags.writeable = False  # a read-only view: the caller's array is untouched
            width = len(_GROUPS[f.name])
            shape = (n,) if width == 1 else (n, width)
            if array.shape != shape:
                problems.append(f"{f.name} has shape {array.shape}, expected {shape}")
            object.__setattr__(self, f.name, array)
        if problems:
            raise MetricsError("frame arrays disagree: " + "; ".join(problems))

    def __len__(self) -> int:
        """Number of frames."""
        return len(self.t_sim)

    @classmethod
    def from_matrix(cls, matrix: npt.NDArray[Any]) -> FrameArrays:
        """Build from an (n, k) float matrix whose columns are :data:`REQUIRED_COLUMNS`.

        Same values as :meth:`from_columns` of those columns, with at most one copy: the
        matrix is laid out column-major so that every field is a contiguous view.
        """
        data = np.asfortranarray(matrix, dtype=np.float64).reshape(
            (-1, len(REQUIRED_COLUMNS)), order="F"
        )
        blocks: dict[str, FloatArray] = {}
        at = 0
        for name, cols in _GROUPS.items():
            width = len(cols)
            blocks[name] = data[:, at] if width == 1 else data[:, at : at + width]
            at += width
        return cls(**blocks)

    @classmethod
    def from_columns(cls, columns: Mapping[str, Column]) -> FrameArrays:
        """Build from frames.csv-named columns of one trial (further columns are ignored).

        Raises :class:`MetricsError` naming every missing column, every column that is not
        one-dimensional numbers, and columns whose lengths differ.
        """
        missing = [c for c in REQUIRED_COLUMNS if c not in columns]
        if missing:
            raise MetricsError(
                f"frames are missing column(s) {', '.join(missing)}; frames.csv must have them"
            )
        arrays: dict[str, FloatArray] = {}
        bad: list[str] = []
        for name in REQUIRED_COLUMNS:
            try:
                arrays[name] = np.asarray(columns[name], dtype=np.float64)
            except (TypeError, ValueError):
                bad.append(name)
                continue
            if arrays[name].ndim != 1:
                bad.append(name)
        if bad:
            raise MetricsError(
                f"frame column(s) {', '.join(bad)} must be one-dimensional sequences of numbers"
            )
        lengths = {name: len(a) for name, a in arrays.items()}
        if len(set(lengths.values())) > 1:
            n = lengths["t_sim"]
            odd = ", ".join(f"{c} ({k})" for c, k in lengths.items() if k != n)
            raise MetricsError(f"frame columns must all have t_sim's length {n}; not {odd}")
        # (k, n) stacks transposed: each column stays contiguous, so per-frame reductions
        # over a block's k columns run over whole contiguous columns.
        groups = {
            name: arrays[cols[0]].copy()
            if len(cols) == 1
            else np.stack([arrays[c] for c in cols]).T
            for name, cols in _GROUPS.items()
        }
        return cls(**groups)

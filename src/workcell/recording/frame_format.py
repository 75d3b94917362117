"""Captured frames into the frame columns, in bulk.

The counterpart of :mod:`workcell.recording.frame_capture`: positions, velocities and TCP
poses come from the state rows, the command, device input and diagnostics from each
frame's extras, the ``boxes`` JSON from the box poses and states. Values are those of the
frame columns (:data:`workcell.record.columns.FRAME_COLUMNS`); a missing device value is
NaN among the reals (stored as NULL) and None among the integers.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import mujoco
import numpy as np
from numpy.typing import NDArray

from workcell.control.ik_residual import residuals
from workcell.record.batch import RowBatch
from workcell.record.quaternion_sign import continuous
from workcell.record.schema import FRAMES
from workcell.recording.frame_capture import (
    BOX_STATES,
    CAPTURED_INTEGERS,
    COMMAND_REALS,
    DEVICE_VALUES,
    CapturedFrames,
    FrameCapture,
    FrameLayout,
    OperatorInput,
)

if TYPE_CHECKING:
    from workcell.control.command import Command
    from workcell.control.controller import RobotController
    from workcell.sim.world import World

REAL_COLUMNS: tuple[str, ...] = FRAMES.of_kind("real")
"""The frame's real columns, in the order of a formatted real matrix."""
INTEGER_COLUMNS: tuple[str, ...] = FRAMES.of_kind("integer")
"""The frame's integer columns (``frame_index`` first), in the order of a formatted row."""

_QUATERNION_COLUMNS = np.r_[11:15, 18:22]
"""Where the left and right TCP quaternions sit in a real matrix."""
_STATE_WIDTH = 54
"""base pose (3), base velocity (3), both TCP poses (14), q (17), dq (17)."""


def real_matrix(
    frames: CapturedFrames, previous_quaternions: NDArray[np.float64] | None = None
) -> NDArray[np.float64]:
    """(n, len(REAL_COLUMNS)): every real column of the frames. The TCP quaternions are
    made continuous (:mod:`workcell.record.quaternion_sign`), the first frame's against
    ``previous_quaternions`` (2, 4): the left and right TCP of the frame before, if any."""
    layout, rows = frames.layout, frames.rows
    n = len(frames)
    nq, nv = layout.nq, layout.nv
    qpos, qvel = rows[:n, :nq], rows[:n, nq : nq + nv]
    at = layout.tcp_at
    quats = np.empty((n, 2, 4))
    for i in range(n):
        mujoco.mju_mat2Quat(quats[i, 0], rows[i, at + 6 : at + 15])
        mujoco.mju_mat2Quat(quats[i, 1], rows[i, at + 15 : at + 24])
    quats = continuous(quats, previous_quaternions)
    command = rows[:n, layout.command_at : layout.command_at + COMMAND_REALS]
    device = rows[:n, layout.device_at : layout.device_at + DEVICE_VALUES]
    real = np.empty((n, len(REAL_COLUMNS)))
    real[:, 0:2] = command[:, 0:2]
    real[:, 2:5] = qpos[:, layout.base_qpos]
    real[:, 5:8] = qvel[:, layout.base_dof]
    real[:, 8:11] = rows[:n, at : at + 3]
    real[:, 11:15] = quats[:, 0]
    real[:, 15:18] = rows[:n, at + 3 : at + 6]
    real[:, 18:22] = quats[:, 1]
    joints = len(layout.joint_qpos)
    real[:, 22 : 22 + joints] = qpos[:, layout.joint_qpos]
    real[:, 22 + joints : 2 + _STATE_WIDTH] = qvel[:, layout.joint_dof]
    # grip and trigger: the device's, or without a device the follow flags and the
    # gripper commands (what input_from_command says a command-only operator pressed)
    follow = rows[:n, layout.integers_at : layout.integers_at + 2]
    no_device = np.isnan(device[:, 0:1])
    real[:, 56:58] = np.where(no_device, follow, device[:, 0:2])
    real[:, 58:60] = np.where(no_device, command[:, 19:21], device[:, 2:4])
    fingers = qpos[:, layout.finger_qpos]
    real[:, 60] = (fingers[:, 0] + fingers[:, 1]) / layout.finger_span
    real[:, 61] = (fingers[:, 2] + fingers[:, 3]) / layout.finger_span
    real[:, 62:83] = command[:, 2:23]
    real[:, 83:108] = device[:, 4:29]
    real[:, 108] = command[:, 23]
    ik_tcp, ik_target = rows[:n, at + 24 : at + 30], rows[:n, at + 30 : at + 36]
    real[:, 109:111] = residuals(ik_tcp.reshape(-1, 3), ik_target.reshape(-1, 3)).reshape(n, 2)
    real[:, 111] = device[:, 29]
    real[:, 112:133] = device[:, 30:51]
    real[:, 133] = rows[:n, layout.task_at + 1]
    real[:, 134] = rows[:n, layout.task_at + 2]
    return real


class FrameFormatter:
    """Formats captured frames into store rows. Keeps each box's text while its state and
    rounded pose stay the same (parked boxes, boxes at rest): formatting floats is most of
    the cost of the ``boxes`` column. Keeps the last TCP quaternions of the trial it
    formats, so that a trial's quaternions stay continuous across batches (a trial's
    frames arrive in order; frame 0 starts afresh)."""

    def __init__(self) -> None:
        self._quaternion_tail: tuple[str, NDArray[np.float64]] | None = None
        self._layout: FrameLayout | None = None
        self._box_columns: NDArray[np.intp] = np.zeros(0, dtype=np.intp)
        self._box_text: list[tuple[tuple[str, list[float]], str] | None] = []

    def batch(
        self, frames: CapturedFrames, session_id: str, trial_id: str, first_index: int
    ) -> RowBatch:
        """The frames as rows of the frames table, numbered from ``first_index``."""
        tail = self._quaternion_tail
        previous = tail[1] if tail is not None and first_index > 0 and tail[0] == trial_id else None
        real = real_matrix(frames, previous)
        if len(frames):
            self._quaternion_tail = (trial_id, real[-1, _QUATERNION_COLUMNS].reshape(2, 4))
        layout = frames.layout
        at, device_at = layout.integers_at, layout.device_at
        buttons = device_at + DEVICE_VALUES - 2
        integer: list[tuple[int | None, ...]] = [
            (first_index + i, *(None if math.isnan(v) else int(v) for v in values))
            for i, values in enumerate(
                np.concatenate(
                    (
                        frames.rows[:, at : at + 2],
                        frames.rows[:, buttons : buttons + 2],
                        frames.rows[:, at + 2 : at + CAPTURED_INTEGERS],
                    ),
                    axis=1,
                ).tolist()
            )
        ]
        boxes = self.boxes_json(frames)
        stages = stage_names(frames)
        text: list[tuple[str | None, ...]] = [
            (session_id, trial_id, b, s) for b, s in zip(boxes, stages, strict=True)
        ]
        return RowBatch(FRAMES, text, real, integer)

    def boxes_json(self, frames: CapturedFrames) -> list[str]:
        """Each frame's ``[[index, state, x, y, z, qw, qx, qy, qz], ...]``, poses to the
        micrometre (-0.0 written 0.0)."""
        layout = frames.layout
        self._use(layout)
        poses = np.round(frames.rows[:, self._box_columns], 6) + 0.0
        states = frames.rows[:, layout.boxes_at : layout.device_at].astype(np.intp)
        width = 7
        prefixes = [f'[{index},"' for index in layout.box_index]
        out = []
        for codes, values in zip(states.tolist(), poses.tolist(), strict=True):
            parts = []
            for k, code in enumerate(codes):
                state = BOX_STATES[code]
                pose = values[k * width : (k + 1) * width]
                key = (state, pose)
                cached = self._box_text[k]
                if cached is None or cached[0] != key:
                    text = f'{prefixes[k]}{state}",{",".join(map(repr, pose))}]'
                    cached = self._box_text[k] = (key, text)
                parts.append(cached[1])
            out.append(f"[{','.join(parts)}]")
        return out

    def _use(self, layout: FrameLayout) -> None:
        if layout != self._layout:
            self._layout = layout
            self._box_columns = np.array(
                [q + k for q in layout.box_qpos for k in range(7)], dtype=np.intp
            )
            self._box_text = [None] * len(layout.box_qpos)


def stage_names(frames: CapturedFrames) -> list[str | None]:
    """Each frame's stage by name (None where not known)."""
    names = frames.layout.stages
    out: list[str | None] = []
    for value in frames.rows[:, frames.layout.task_at].tolist():
        known = not math.isnan(value) and 0 <= int(value) < len(names)
        out.append(names[int(value)] if known else None)
    return out


class FrameReader:
    """Frames of one world by column name, one at a time (for an environment's
    observation): capture and formatting set up once. Successive reads are successive
    frames of one trial (quaternions continuous) until :meth:`restart`."""

    def __init__(self, world: World, controller: RobotController) -> None:
        self._capture = FrameCapture(world, controller, capacity=1)
        self._formatter = FrameFormatter()
        self._index = 0

    def restart(self) -> None:
        """The next read is the first frame of a new trial."""
        self._index = 0

    def read(
        self,
        command: Command,
        operator_input: OperatorInput | None,
        *,
        t_sim: float,
        t_wall: float,
        step_wall_ms: float,
    ) -> dict[str, Any]:
        """As :func:`build_frame`."""
        self._capture.capture(
            command, operator_input, t_sim=t_sim, step_wall_ms=step_wall_ms, t_wall=t_wall
        )
        batch = self._formatter.batch(self._capture.take(), "", "", self._index)
        self._index += 1
        return _as_dict(batch)


def build_frame(
    world: World,
    controller: RobotController,
    command: Command,
    operator_input: OperatorInput,
    *,
    t_sim: float,
    t_wall: float,
    step_wall_ms: float,
) -> dict[str, Any]:
    """Every frame column but ``session_id``, ``trial_id`` and ``frame_index``, by name,
    of the world now (no value as None): what the recorder would store."""
    return FrameReader(world, controller).read(
        command, operator_input, t_sim=t_sim, t_wall=t_wall, step_wall_ms=step_wall_ms
    )


def _as_dict(batch: RowBatch) -> dict[str, Any]:
    """The one row of ``batch`` by column name, ids and index left out."""
    row: dict[str, Any] = {
        name: None if math.isnan(value) else value
        for name, value in zip(REAL_COLUMNS, batch.real[0].tolist(), strict=True)
    }
    row.update(zip(INTEGER_COLUMNS[1:], batch.integer[0][1:], strict=True))
    row["boxes"] = batch.text[0][2]
    row["stage"] = batch.text[0][3]
    return row

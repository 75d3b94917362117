"""Capturing a frame at its sample instant, at the least cost to the simulation.

At the sample instant only numbers are copied, into one row of a float matrix: the
world's joint positions and velocities, the two TCP site poses, where the IK has each TCP
and its target (the IK residuals are computed from them later), the command and the
operator's input, the grasp signals and the boxes' states. Turning rows into the frame's
columns (:mod:`workcell.recording.frame_format`) happens later, in bulk, and when recording
through a :class:`~workcell.recording.store_process.StoreProcess`, in the writer process.
"""

from __future__ import annotations

import math
import struct
import time
from dataclasses import dataclass
from typing import TYPE_CHECKING

import mujoco
import numpy as np
from numpy.typing import NDArray

from workcell.sim.boxes import BoxState
from workcell.sim.joints import BASE_JOINTS, FINGER_JOINTS, JOINT_ORDER, SIDES

if TYPE_CHECKING:  # the writer process formats frames without the simulation's modules
    from workcell.control.command import Command
    from workcell.control.controller import RobotController
    from workcell.sim.world import World

Pose = tuple[float, float, float, float, float, float, float]

BOX_STATES: tuple[str, ...] = ("parked", "active", "delivered")
"""How a box's state is written in the ``boxes`` column; a row holds its position here."""
_STATE_NUMBER = {
    BoxState.PARKED: 0.0,
    BoxState.ACTIVE: 1.0,
    BoxState.DELIVERED: 2.0,
}


@dataclass(frozen=True)
class OperatorInput:
    """Raw device state of a human operator (VR or desktop), as it arrived, and the poses
    the teleoperation acted on.

    Poses are (x, y, z, qw, qx, qy, qz) in the operator's tracking frame; None when the
    device has no such part. ``age_s`` is how old the input was when the frame was taken.
    ``filtered_*`` are the controller and headset poses after the session's pose filter
    (the raw ones when it is off).
    """

    grip: tuple[float, float]
    trigger: tuple[float, float]
    controller_l: Pose | None = None
    controller_r: Pose | None = None
    headset: Pose | None = None
    stick_l: tuple[float, float] | None = None
    stick_r: tuple[float, float] | None = None
    buttons: tuple[int, int] | None = None
    age_s: float | None = None
    filtered_l: Pose | None = None
    filtered_r: Pose | None = None
    filtered_headset: Pose | None = None


def input_from_command(command: Command) -> OperatorInput:
    """What a command-only operator (the expert, a replay) "pressed": grip is the follow
    flag and trigger the gripper command, so grip-gated metrics mean the same for all."""
    return OperatorInput(
        grip=(float(command.left.follow), float(command.right.follow)),
        trigger=(command.close_left, command.close_right),
    )


@dataclass(frozen=True)
class FrameLayout:
    """Where a frame's values sit in a captured row (plain numbers, so that it travels to a
    writer process cheaply). A row holds, in this order:

    - the state: ``qpos`` (nq), ``qvel`` (nv), the TCP sites' positions (2 x 3) and
      rotation matrices (2 x 9), the IK configuration's TCP positions (2 x 3) and the IK
      targets' positions (2 x 3), left first;
    - :data:`COMMAND_REALS` reals: t_sim, t_wall, the command's 21 columns (base twist,
      both arm targets, both gripper commands, head) and step_wall_ms;
    - :data:`CAPTURED_INTEGERS` integers: follow_l, follow_r, contact_l, contact_r,
      attached (-1 for none);
    - each box's state (its position in :data:`BOX_STATES`);
    - :data:`DEVICE_VALUES` values of the operator's device: grip (2), trigger (2), both
      controllers and the headset (3 x 7), both thumbsticks (2 x 2), input age, the
      three poses filtered (3 x 7), buttons (2); NaN where the device has no such part,
      and all NaN without a device (a command-only operator: grip and trigger then read
      from the command, as :func:`input_from_command` says);
    - :data:`TASK_VALUES` values of the task's judgement: the stage (its position in
      :attr:`stages`) and the progress (0..1), NaN where not known; then whether a person
      who took over drove (``intervention``: 1 or 0, NaN where not known).
    """

    nq: int
    nv: int
    base_qpos: tuple[int, ...]
    base_dof: tuple[int, ...]
    joint_qpos: tuple[int, ...]
    joint_dof: tuple[int, ...]
    finger_qpos: tuple[int, ...]
    """Both fingers of the left gripper, then of the right."""
    finger_span: float
    """Sum of both fingers' travel: opening = (a + b) / span."""
    box_qpos: tuple[int, ...]
    """Each box's free-joint qpos address (x, y, z, qw, qx, qy, qz follow)."""
    box_index: tuple[int, ...]
    stages: tuple[str, ...] = ()
    """The task's stages, in order (the ``stage`` column names one by its position)."""

    @property
    def tcp_at(self) -> int:
        """Where the TCP poses start: positions (6), rotation matrices (18), the IK's TCP
        positions (6) and its targets' positions (6)."""
        return self.nq + self.nv

    @property
    def command_at(self) -> int:
        return self.tcp_at + 36

    @property
    def integers_at(self) -> int:
        return self.command_at + COMMAND_REALS

    @property
    def boxes_at(self) -> int:
        return self.integers_at + CAPTURED_INTEGERS

    @property
    def device_at(self) -> int:
        return self.boxes_at + len(self.box_qpos)

    @property
    def task_at(self) -> int:
        return self.device_at + DEVICE_VALUES

    @property
    def width(self) -> int:
        return self.task_at + TASK_VALUES

    @classmethod
    def of(cls, world: World, stages: tuple[str, ...] = ()) -> FrameLayout:
        model = world.model

        def qpos(name: str) -> int:
            return int(model.jnt_qposadr[model.joint(name).id])

        def dof(name: str) -> int:
            return int(model.jnt_dofadr[model.joint(name).id])

        finger = model.joint(FINGER_JOINTS["l"][0]).id
        return cls(
            nq=model.nq,
            nv=model.nv,
            base_qpos=tuple(qpos(n) for n in BASE_JOINTS),
            base_dof=tuple(dof(n) for n in BASE_JOINTS),
            joint_qpos=tuple(qpos(n) for n in JOINT_ORDER),
            joint_dof=tuple(dof(n) for n in JOINT_ORDER),
            finger_qpos=tuple(qpos(n) for side in SIDES for n in FINGER_JOINTS[side]),
            finger_span=2.0 * float(model.jnt_range[finger][1]),
            box_qpos=tuple(slot.qpos for slot in world.boxes.slots),
            box_index=tuple(slot.index for slot in world.boxes.slots),
            stages=stages,
        )


COMMAND_REALS = 24
"""t_sim, t_wall, the command's 21 real columns and step_wall_ms."""
CAPTURED_INTEGERS = 5
"""follow_l, follow_r, contact_l, contact_r, attached."""
DEVICE_VALUES = 53
"""grip (2), trigger (2), controller_l, controller_r, headset (7 each), stick_l, stick_r
(2 each), age_s, the three poses filtered (7 each), buttons (2)."""
TASK_VALUES = 3
"""The stage's position in the task's stages, the progress, and the intervention flag."""

NAN = math.nan
_NO_POSE: tuple[float, ...] = (NAN,) * 7
_NO_PAIR: tuple[float, float] = (NAN, NAN)


def device_values(device: OperatorInput) -> tuple[float, ...]:
    """The :data:`DEVICE_VALUES` values of ``device`` in row order (NaN for a missing
    part)."""
    return (
        *device.grip,
        *device.trigger,
        *(device.controller_l or _NO_POSE),
        *(device.controller_r or _NO_POSE),
        *(device.headset or _NO_POSE),
        *(device.stick_l or _NO_PAIR),
        *(device.stick_r or _NO_PAIR),
        NAN if device.age_s is None else device.age_s,
        *(device.filtered_l or _NO_POSE),
        *(device.filtered_r or _NO_POSE),
        *(device.filtered_headset or _NO_POSE),
        *(device.buttons or _NO_PAIR),
    )


@dataclass(frozen=True)
class CapturedFrames:
    """Consecutive captured frames of one trial: one row each (see :class:`FrameLayout`)."""

    layout: FrameLayout
    rows: NDArray[np.float64]
    """(n, layout.width)"""

    def __len__(self) -> int:
        return len(self.rows)


class FrameCapture:
    """Captures frames of one world into a buffer of ``capacity`` rows.

    A capture is what recording costs the simulation at every frame, in its thread, so it
    does the least it can: one :func:`mujoco.mj_kinematics`, one concatenate of views
    into the state and one :class:`struct.Struct` packing of the other numbers straight
    into the row, with no object made on the way."""

    def __init__(
        self,
        world: World,
        controller: RobotController,
        capacity: int,
        stages: tuple[str, ...] = (),
    ) -> None:
        self.world = world
        self.layout = layout = FrameLayout.of(world, stages)
        self.capacity = capacity
        model = world.model
        self._rows = np.full((capacity, layout.width), NAN)
        self._buffer = self._rows.data.cast("B")  # what the packing writes into
        self._count = 0
        # Views of the state a row starts with, in row order: the world and the IK each
        # keep one MjData, whose arrays keep their memory for its life, and the IK keeps
        # its targets in one array, so the views are made once.
        data, ik = world.data, controller.ik
        sites = [model.site(f"tcp_{side}").id for side in SIDES]
        ik_sites = [ik.tcp_sites[side] for side in SIDES]
        self._state = (
            data.qpos,
            data.qvel,
            *_rows_of(data.site_xpos, sites),
            *_rows_of(data.site_xmat, sites),
            *_rows_of(ik.configuration.data.site_xpos, ik_sites),
            ik.target_positions.reshape(-1),
        )
        self._slots = world.boxes.slots
        self._pack = struct.Struct(f"={layout.device_at - layout.command_at}d").pack_into
        self._pack_device = struct.Struct(f"={DEVICE_VALUES}d").pack_into
        self._row_bytes = layout.width * 8
        self._device_rows: set[int] = set()
        """Rows whose device values were written (the others hold NaN)."""

    def __len__(self) -> int:
        return self._count

    @property
    def full(self) -> bool:
        return self._count >= self.capacity

    def capture(
        self,
        command: Command,
        operator_input: OperatorInput | None,
        *,
        t_sim: float,
        step_wall_ms: float,
        t_wall: float | None = None,
        stage: int = -1,
        progress: float = NAN,
        intervention: float = 0.0,
    ) -> None:
        """Copy the state of this instant (``t_sim`` on the trial clock, ``t_wall`` Unix
        seconds, now if not given), of the operator's device (None for a command-only
        operator, see :func:`input_from_command`) and the task's judgement (``stage``: its
        position in the layout's stages, -1 for none) and whether a person who took over
        drives (``intervention`` 1, else 0); the buffer must not be :attr:`full`."""
        world = self.world
        # After mj_step the body and site poses are those of the step's start; bring them up
        # to the joint positions so that every pose in the frame belongs to the same instant.
        mujoco.mj_kinematics(world.model, world.data)
        count = self._count
        at = self.layout.command_at
        rows = self._rows
        np.concatenate(self._state, out=rows[count, :at])
        base, left, right = command.base, command.left, command.right
        grasp = world.grasp
        contact_l, contact_r, holding = grasp.contact_l, grasp.contact_r, grasp.holding
        self._pack(
            self._buffer,
            count * self._row_bytes + at * 8,
            t_sim,
            time.time() if t_wall is None else t_wall,
            base.vx,
            base.vy,
            base.wz,
            *left.position,
            *left.quaternion,
            *right.position,
            *right.quaternion,
            command.close_left,
            command.close_right,
            *command.head,
            step_wall_ms,
            left.follow,
            right.follow,
            -1 if contact_l is None else contact_l.index,
            -1 if contact_r is None else contact_r.index,
            -1 if holding is None else holding.index,
            *[_STATE_NUMBER[slot.state] for slot in self._slots],
        )
        if operator_input is not None:
            at = count * self._row_bytes + self.layout.device_at * 8
            self._pack_device(self._buffer, at, *device_values(operator_input))
            self._device_rows.add(count)
        elif count in self._device_rows:
            rows[count, self.layout.device_at :] = NAN
            self._device_rows.discard(count)
        self._count = count + 1
        rows[count, self.layout.task_at + 2] = intervention
        self.judged(stage, progress)

    def judged(self, stage: int, progress: float) -> None:
        """Set the task's judgement of the latest frame captured (``stage``: a position
        in the layout's stages, -1 for none)."""
        if self._count:
            at = self.layout.task_at
            self._rows[self._count - 1, at : at + 2] = (
                NAN if stage < 0 else stage,
                progress,
            )

    def take(self) -> CapturedFrames:
        """The frames captured since the last take (the buffer is emptied)."""
        frames = CapturedFrames(self.layout, self._rows[: self._count].copy())
        self._count = 0
        return frames


def _rows_of(array: NDArray[np.float64], rows: list[int]) -> list[NDArray[np.float64]]:
    """Views of ``array``'s ``rows``, flattened: one view when the rows are consecutive
    (fewer arrays to concatenate at each frame)."""
    if rows == list(range(rows[0], rows[0] + len(rows))):
        return [array[rows[0] : rows[0] + len(rows)].reshape(-1)]
    return [array[row] for row in rows]

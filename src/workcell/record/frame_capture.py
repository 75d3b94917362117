"""Capturing a frame at its sample instant, at the least cost to the simulation.

At the sample instant only numbers are copied, into one row of a float matrix: the
world's joint positions and velocities, the two TCP site poses, the command and the
operator's input, the grasp signals and the boxes' states. Turning rows into the frame's
columns (:mod:`workcell.record.frame_format`) happens later, in bulk, and when recording
through a :class:`~workcell.record.store_process.StoreProcess`, in the writer process.
"""

from __future__ import annotations

import math
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
    """Raw device state of a human operator (VR or desktop), as it arrived.

    Poses are (x, y, z, qw, qx, qy, qz) in the operator's tracking frame; None when the
    device has no such part. ``age_s`` is how old the input was when the frame was taken.
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


def input_from_command(command: Command) -> OperatorInput:
    """What a command-only operator (the expert, a replay) "pressed": grip is the follow
    flag and trigger the gripper command, so grip-gated metrics mean the same for all."""
    return OperatorInput(
        grip=(float(command.left.follow), float(command.right.follow)),
        trigger=(command.gripper_left, command.gripper_right),
    )


@dataclass(frozen=True)
class FrameLayout:
    """Where a frame's values sit in a captured row: ``qpos`` (nq), ``qvel`` (nv), the
    TCP sites' positions (2 x 3) and rotation matrices (2 x 9), left first, then
    :data:`EXTRA_REALS` values (see :func:`extra_reals`), :data:`EXTRA_INTEGERS` integers
    (NaN for none) and each box's state (its position in :data:`BOX_STATES`).
    Plain numbers, so that it travels to a writer process cheaply."""

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

    @property
    def extras_at(self) -> int:
        """Where the extra reals start; the integers and box states follow them."""
        return self.nq + self.nv + 24

    @property
    def width(self) -> int:
        return self.extras_at + EXTRA_REALS + EXTRA_INTEGERS + len(self.box_qpos)

    @classmethod
    def of(cls, world: World) -> FrameLayout:
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
        )


EXTRA_REALS = 56
"""Real values of a frame that are not the world's state (see :func:`extra_reals`)."""
EXTRA_INTEGERS = 7
"""follow_l, follow_r, buttons_l, buttons_r, contact_l, contact_r, attached."""

NAN = math.nan
_NO_POSE: tuple[float, ...] = (NAN,) * 7
_NO_PAIR: tuple[float, float] = (NAN, NAN)


def extra_reals(
    command: Command,
    device: OperatorInput,
    *,
    t_sim: float,
    t_wall: float,
    step_wall_ms: float,
    ik_residuals: tuple[float, float],
) -> tuple[float, ...]:
    """t_sim, t_wall, then grip and trigger (4), then the command columns but the follow
    flags (21), the device columns (25), step_wall_ms, both IK residuals and
    input_age_s: the frame's real columns in table order, less the state's."""
    base, left, right = command.base, command.left, command.right
    return (
        t_sim,
        t_wall,
        device.grip[0],
        device.grip[1],
        device.trigger[0],
        device.trigger[1],
        base.vx,
        base.vy,
        base.wz,
        *left.position,
        *left.quaternion,
        *right.position,
        *right.quaternion,
        command.gripper_left,
        command.gripper_right,
        command.head[0],
        command.head[1],
        *(device.controller_l or _NO_POSE),
        *(device.controller_r or _NO_POSE),
        *(device.headset or _NO_POSE),
        *(device.stick_l or _NO_PAIR),
        *(device.stick_r or _NO_PAIR),
        step_wall_ms,
        ik_residuals[0],
        ik_residuals[1],
        NAN if device.age_s is None else device.age_s,
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
    """Captures frames of one world into a buffer of ``capacity`` rows."""

    def __init__(self, world: World, controller: RobotController, capacity: int) -> None:
        self.world = world
        self.ik = controller.ik
        self.layout = FrameLayout.of(world)
        self.capacity = capacity
        model = world.model
        self._sites = [model.site(f"tcp_{side}").id for side in SIDES]
        self._rows = np.empty((capacity, self.layout.width))
        self._count = 0
        # Views of the state a row starts with, in row order: the world keeps one MjData,
        # whose arrays keep their memory for its life, so the views are made once.
        data = world.data
        left, right = self._sites
        self._state = (
            data.qpos,
            data.qvel,
            data.site_xpos[left],
            data.site_xpos[right],
            data.site_xmat[left],
            data.site_xmat[right],
        )

    def __len__(self) -> int:
        return self._count

    @property
    def full(self) -> bool:
        return self._count >= self.capacity

    def capture(
        self,
        command: Command,
        operator_input: OperatorInput,
        *,
        t_sim: float,
        step_wall_ms: float,
        t_wall: float | None = None,
    ) -> None:
        """Copy the state of this instant (``t_sim`` on the trial clock, ``t_wall`` Unix
        seconds, now if not given); the buffer must not be :attr:`full`."""
        world = self.world
        # After mj_step the body and site poses are those of the step's start; bring them up
        # to the joint positions so that every pose in the frame belongs to the same instant.
        mujoco.mj_kinematics(world.model, world.data)
        row = self._rows[self._count]
        at = self.layout.extras_at
        np.concatenate(self._state, out=row[:at])
        grasp = world.grasp
        holding = grasp.holding
        buttons = operator_input.buttons
        ik = self.ik
        extras = extra_reals(
            command,
            operator_input,
            t_sim=t_sim,
            t_wall=time.time() if t_wall is None else t_wall,
            step_wall_ms=step_wall_ms,
            ik_residuals=(ik.residual("l"), ik.residual("r")),
        )
        integers = (
            command.left.follow,
            command.right.follow,
            NAN if buttons is None else buttons[0],
            NAN if buttons is None else buttons[1],
            -1 if grasp.contact_l is None else grasp.contact_l.index,
            -1 if grasp.contact_r is None else grasp.contact_r.index,
            -1 if holding is None else holding.index,
        )
        row[at:] = (*extras, *integers, *[_STATE_NUMBER[slot.state] for slot in world.boxes.slots])
        self._count += 1

    def take(self) -> CapturedFrames:
        """The frames captured since the last take (the buffer is emptied)."""
        frames = CapturedFrames(self.layout, self._rows[: self._count].copy())
        self._count = 0
        return frames

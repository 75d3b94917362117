"""One frame of the record: the robot, the boxes, the command and the operator's input.

Built from the live simulation at a sample instant. Keys are the frame column names of
:mod:`workcell.record.columns` (all but the ids and the index, which the store assigns).
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from typing import Any

import mujoco
import numpy as np

from workcell.control.command import ArmCommand, Command
from workcell.control.controller import RobotController
from workcell.record.columns import POSE_SUFFIXES
from workcell.sim.boxes import BoxState
from workcell.sim.joints import JOINT_ORDER
from workcell.sim.world import World

Pose = tuple[float, float, float, float, float, float, float]


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


_Q_COLUMNS = tuple(f"q_{j}" for j in JOINT_ORDER)
_DQ_COLUMNS = tuple(f"dq_{j}" for j in JOINT_ORDER)
_STATE_CODE = {
    BoxState.PARKED: "parked",
    BoxState.ACTIVE: "active",
    BoxState.DELIVERED: "delivered",
}


_POSE_NAMES = {
    prefix: tuple(f"{prefix}_{s}" for s in POSE_SUFFIXES)
    for prefix in ("tcp_l", "tcp_r", "target_l", "target_r", "ctrl_l", "ctrl_r", "headset")
}
_NO_POSE = {prefix: dict.fromkeys(names) for prefix, names in _POSE_NAMES.items()}


def _pose(prefix: str, values: Any) -> dict[str, float | None]:
    if values is None:
        return _NO_POSE[prefix]
    return dict(zip(_POSE_NAMES[prefix], map(float, values), strict=True))


def _target(prefix: str, arm: ArmCommand) -> dict[str, float | None]:
    return _pose(prefix, (*arm.position, *arm.quaternion))


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
    """Every frame column except ``session_id``, ``trial_id`` and ``frame_index``."""
    # After mj_step the body and site poses are those of the step's start; bring them up to
    # the joint positions so that every pose in the frame belongs to the same instant.
    mujoco.mj_kinematics(world.model, world.data)
    base = world.base_pose
    velocity = world.base_velocity
    row: dict[str, Any] = {
        "t_sim": t_sim,
        "t_wall": t_wall,
        "base_x": float(base[0]),
        "base_y": float(base[1]),
        "base_yaw": float(base[2]),
        "base_vx": float(velocity[0]),
        "base_vy": float(velocity[1]),
        "base_wz": float(velocity[2]),
    }
    for side in ("l", "r"):
        position, quaternion = world.tcp_pose(side)
        row.update(_pose(f"tcp_{side}", (*position, *quaternion)))
    row.update(zip(_Q_COLUMNS, world.joint_positions.tolist(), strict=True))
    row.update(zip(_DQ_COLUMNS, world.joint_velocities.tolist(), strict=True))
    grasp = world.grasp
    row.update(
        {
            "grip_l": operator_input.grip[0],
            "grip_r": operator_input.grip[1],
            "trigger_l": operator_input.trigger[0],
            "trigger_r": operator_input.trigger[1],
            "gripper_l": world.gripper_opening("l"),
            "gripper_r": world.gripper_opening("r"),
            "cmd_vx": command.base.vx,
            "cmd_vy": command.base.vy,
            "cmd_wz": command.base.wz,
            **_target("target_l", command.left),
            **_target("target_r", command.right),
            "follow_l": int(command.left.follow),
            "follow_r": int(command.right.follow),
            "gripper_cmd_l": command.gripper_left,
            "gripper_cmd_r": command.gripper_right,
            "head_cmd_pan": command.head[0],
            "head_cmd_tilt": command.head[1],
            **_pose("ctrl_l", operator_input.controller_l),
            **_pose("ctrl_r", operator_input.controller_r),
            **_pose("headset", operator_input.headset),
            "stick_l_x": _item(operator_input.stick_l, 0),
            "stick_l_y": _item(operator_input.stick_l, 1),
            "stick_r_x": _item(operator_input.stick_r, 0),
            "stick_r_y": _item(operator_input.stick_r, 1),
            "buttons_l": None if operator_input.buttons is None else operator_input.buttons[0],
            "buttons_r": None if operator_input.buttons is None else operator_input.buttons[1],
            "contact_l": -1 if grasp.contact_l is None else grasp.contact_l.index,
            "contact_r": -1 if grasp.contact_r is None else grasp.contact_r.index,
            "attached": -1 if grasp.holding is None else grasp.holding.index,
            "boxes": _boxes_json(world),
            "step_wall_ms": step_wall_ms,
            "ik_residual_l": controller.ik.residual("l"),
            "ik_residual_r": controller.ik.residual("r"),
            "input_age_s": operator_input.age_s,
        }
    )
    return row


def _item(pair: tuple[float, float] | None, index: int) -> float | None:
    return None if pair is None else float(pair[index])


def _boxes_json(world: World) -> str:
    """``[[index, state, x, y, z, qw, qx, qy, qz], ...]``, poses to the micrometre."""
    pool = world.boxes
    poses = np.round(world.data.qpos[pool.pose_indices], 6).tolist()
    boxes = [
        [slot.index, _STATE_CODE[slot.state], *pose]
        for slot, pose in zip(pool.slots, poses, strict=True)
    ]
    return json.dumps(boxes, separators=(",", ":"))

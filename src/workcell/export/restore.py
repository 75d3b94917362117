"""Put a world into a recorded frame's state, so it can be rendered or checked.

The frame columns hold everything the pose of the scene depends on: the base pose
(``base_x``, ``base_y``, ``base_yaw`` are the base joints), the 17 joints, the finger
openings (``gripper_l/r``, both fingers of a hand at the recorded mean) and every box's
pose (the ``boxes`` JSON, onto the boxes' free joints). Velocities are restored where they
are recorded (base and joints) and zero elsewhere; ``mj_forward`` then recomputes every
body, site and camera pose.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import mujoco
import numpy as np
from numpy.typing import NDArray

from workcell.export.boxes import BoxTrack, parse_boxes
from workcell.export.features import column_matrix
from workcell.record.columns import pose_columns
from workcell.sim.joints import BASE_JOINTS, FINGER_JOINTS, JOINT_ORDER, SIDES
from workcell.sim.world import World

Columns = Mapping[str, Sequence[Any] | NDArray[Any]]


@dataclass(frozen=True)
class RecordedStates:
    """The state columns of one trial's frames, as arrays (one row per frame)."""

    base: NDArray[np.float64]
    base_velocity: NDArray[np.float64]
    joints: NDArray[np.float64]
    joint_velocities: NDArray[np.float64]
    grippers: NDArray[np.float64]
    tcp: NDArray[np.float64]
    """(frames, 2, 7): left and right TCP world pose (x, y, z, qw, qx, qy, qz)."""
    boxes: BoxTrack

    @classmethod
    def from_frames(cls, frames: Columns, boxes: BoxTrack | None = None) -> RecordedStates:
        """The states of ``frames``; ``boxes`` is their parsed ``boxes`` column (parsed
        here, without a pool size check, when not given)."""
        if boxes is None:
            boxes = parse_boxes(frames["boxes"])
        return cls(
            base=column_matrix(frames, ("base_x", "base_y", "base_yaw")),
            base_velocity=column_matrix(frames, ("base_vx", "base_vy", "base_wz")),
            joints=column_matrix(frames, [f"q_{j}" for j in JOINT_ORDER]),
            joint_velocities=column_matrix(frames, [f"dq_{j}" for j in JOINT_ORDER]),
            grippers=column_matrix(frames, ("gripper_l", "gripper_r")),
            tcp=np.stack([column_matrix(frames, pose_columns(f"tcp_{s}")) for s in SIDES], 1),
            boxes=boxes,
        )

    def __len__(self) -> int:
        return len(self.base)


class StateRestorer:
    """Writes recorded frames into a :class:`World`'s MuJoCo state."""

    def __init__(self, world: World) -> None:
        self.world = world
        model = world.model

        def addresses(names: Sequence[str]) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
            ids = [model.joint(name).id for name in names]
            return np.array(model.jnt_qposadr[ids]), np.array(model.jnt_dofadr[ids])

        self._base_q, self._base_v = addresses(BASE_JOINTS)
        self._joint_q, self._joint_v = addresses(JOINT_ORDER)
        self._fingers = [addresses(FINGER_JOINTS[side])[0] for side in SIDES]
        self._finger_open = float(model.jnt_range[model.joint(FINGER_JOINTS["l"][0]).id][1])
        self._box_q = [slot.qpos for slot in world.boxes.slots]

    def restore(
        self, states: RecordedStates, i: int, *, back_steps: int = 0, forward: bool = True
    ) -> None:
        """Frame ``i`` of ``states`` into the world's data (then ``mj_forward``).

        ``back_steps`` > 0 moves the base and the joints that many physics steps back along
        their recorded velocities (MuJoCo integrates positions with the new velocity, so one
        step back is exact): the kinematics the recorder saw, see :mod:`.replay`."""
        data = self.world.data
        back = back_steps * self.world.config.timestep
        data.qvel[:] = 0.0
        data.qpos[self._base_q] = states.base[i] - back * states.base_velocity[i]
        data.qvel[self._base_v] = states.base_velocity[i]
        data.qpos[self._joint_q] = states.joints[i] - back * states.joint_velocities[i]
        data.qvel[self._joint_v] = states.joint_velocities[i]
        for side, fingers in enumerate(self._fingers):
            data.qpos[fingers] = states.grippers[i, side] * self._finger_open
        poses = states.boxes.poses[i]
        for index, address in enumerate(self._box_q):
            data.qpos[address : address + 7] = poses[index]
        if forward:
            mujoco.mj_forward(self.world.model, data)

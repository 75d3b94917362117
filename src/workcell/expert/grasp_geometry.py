"""Where the palms go around a box, and which way they face, in the robot's base frame."""

from __future__ import annotations

import math
from dataclasses import dataclass

import mujoco
import numpy as np
from numpy.typing import NDArray

UP = np.array([0.0, 0.0, 1.0])


@dataclass(frozen=True)
class PalmTargets:
    """TCP positions and quaternions (w, x, y, z) for both palms, base frame."""

    left_position: NDArray[np.float64]
    left_quaternion: NDArray[np.float64]
    right_position: NDArray[np.float64]
    right_quaternion: NDArray[np.float64]

    def shifted(self, delta: NDArray[np.float64]) -> PalmTargets:
        return PalmTargets(
            self.left_position + delta,
            self.left_quaternion,
            self.right_position + delta,
            self.right_quaternion,
        )


def _quat_from_axes(x: NDArray[np.float64], y: NDArray[np.float64], z: NDArray[np.float64]) -> NDArray[np.float64]:
    mat = np.column_stack([x, y, z])
    quat = np.zeros(4)
    mujoco.mju_mat2Quat(quat, mat.flatten())
    return quat


def palm_targets(
    center: NDArray[np.float64], grasp_yaw: float, half_width: float, gap: float
) -> PalmTargets:
    """Palms on both sides of a box centred at ``center`` (base frame).

    ``grasp_yaw`` is the heading of the box's grasp axis in the base frame; ``gap`` is the
    distance of each pad face from the box side (negative squeezes into the box).
    """
    axis = np.array([math.cos(grasp_yaw), math.sin(grasp_yaw), 0.0])
    if axis[1] < 0:
        axis = -axis
    offset = axis * (half_width + gap)
    left_z, right_z = -axis, axis
    left_y, right_y = UP, -UP
    left_x, right_x = np.cross(left_y, left_z), np.cross(right_y, right_z)
    return PalmTargets(
        left_position=center + offset,
        left_quaternion=_quat_from_axes(left_x, left_y, left_z),
        right_position=center - offset,
        right_quaternion=_quat_from_axes(right_x, right_y, right_z),
    )

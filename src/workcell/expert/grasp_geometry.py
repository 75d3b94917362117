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


def _quat_from_axes(
    x: NDArray[np.float64], y: NDArray[np.float64], z: NDArray[np.float64]
) -> NDArray[np.float64]:
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
    c, s = math.cos(grasp_yaw), math.sin(grasp_yaw)
    if s < 0:
        c, s = -c, -s
    axis = np.array([c, s, 0.0])
    offset = axis * (half_width + gap)
    # Each palm faces the box (z), keeps its y vertical (up for the left, down for the right),
    # so x = y cross z points the same horizontal way for both: (s, -c, 0).
    x = np.array([s, -c, 0.0])
    return PalmTargets(
        left_position=center + offset,
        left_quaternion=_quat_from_axes(x, UP, -axis),
        right_position=center - offset,
        right_quaternion=_quat_from_axes(x, -UP, axis),
    )

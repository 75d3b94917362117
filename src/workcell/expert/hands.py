"""Where the hands are now, as palm targets: what the expert holds when it takes over a
robot someone else drove, so that its first command does not jump the arms."""

from __future__ import annotations

import math

import numpy as np

from workcell.expert.grasp_geometry import PalmTargets
from workcell.sim.world import World


def _base_quaternion(world: World, quat: np.ndarray) -> np.ndarray:
    """A world-frame orientation (w, x, y, z) in the base frame (turned by -yaw)."""
    half = -float(world.base_pose[2]) / 2
    c, s = math.cos(half), math.sin(half)
    w, x, y, z = (float(v) for v in quat)
    # (c, 0, 0, s) * (w, x, y, z)
    return np.array([c * w - s * z, c * x - s * y, c * y + s * x, c * z + s * w])


def measured_palms(world: World) -> PalmTargets:
    """Both TCPs' measured poses in the base frame."""
    poses = []
    for side in ("l", "r"):
        position, quat = world.tcp_pose(side)
        poses.append((world.to_base_frame(position), _base_quaternion(world, np.asarray(quat))))
    return PalmTargets(poses[0][0], poses[0][1], poses[1][0], poses[1][1])

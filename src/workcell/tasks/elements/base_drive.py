"""How a scripted driver steers the base: a saturated proportional twist toward a goal pose
(x, y, yaw in the world), and when the base has arrived there (close, aligned, slow)."""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from workcell.control.command import BaseTwist
from workcell.sim.world import World

ARRIVED_M = 0.015
ARRIVED_RAD = 0.03


def wrap_angle(angle: float) -> float:
    """``angle`` (rad) in [-pi, pi)."""
    return (angle + math.pi) % (2 * math.pi) - math.pi


def twist_toward(
    world: World, goal: NDArray[np.float64], speed_scale: float, tolerance: float = ARRIVED_M
) -> BaseTwist:
    """A saturated proportional twist toward ``goal`` (x, y, yaw in the world), at most the
    robot's top speeds times ``speed_scale``."""
    pose = world.base_pose
    error_world = goal[:2] - pose[:2]
    distance = float(np.linalg.norm(error_world))
    yaw = float(pose[2])
    c, s = math.cos(yaw), math.sin(yaw)
    error = np.array(
        [c * error_world[0] + s * error_world[1], -s * error_world[0] + c * error_world[1]]
    )
    yaw_error = wrap_angle(float(goal[2]) - yaw)
    r = world.config.robot
    vmax = r.max_linear_speed * speed_scale
    wmax = r.max_yaw_rate * speed_scale
    linear = error * 2.0
    speed = float(np.linalg.norm(linear))
    if speed > vmax:
        linear *= vmax / speed
    if distance < tolerance * 0.5:
        linear[:] = 0.0
    wz = float(np.clip(2.5 * yaw_error, -wmax, wmax))
    return BaseTwist(float(linear[0]), float(linear[1]), wz)


def arrived_at(world: World, goal: NDArray[np.float64], tolerance: float = ARRIVED_M) -> bool:
    """The base is within ``tolerance`` (m) of ``goal``, aligned with it (in proportion)
    and nearly still."""
    pose = world.base_pose
    close = float(np.linalg.norm(goal[:2] - pose[:2])) < tolerance
    aligned = abs(wrap_angle(float(goal[2] - pose[2]))) < ARRIVED_RAD * (tolerance / ARRIVED_M)
    slow = float(np.linalg.norm(world.base_velocity[:2])) < 0.05
    return close and aligned and slow

"""Helpers shared by the MjSpec builders: rotations and the two collision classes."""

from __future__ import annotations

import math

import mujoco
import numpy as np
from numpy.typing import NDArray

# Collision bits: the environment collides with everything, the robot only with the
# environment (arm-arm clearance is the IK's job, not the contact solver's).
ENV_CONTYPE, ENV_CONAFFINITY = 1, 3
ROBOT_CONTYPE, ROBOT_CONAFFINITY = 2, 1

Vec3 = tuple[float, float, float]
Quat = tuple[float, float, float, float]


def quat_axis_angle(axis: Vec3, angle: float) -> Quat:
    """Unit quaternion (w, x, y, z) for a rotation of ``angle`` about ``axis``."""
    ax = np.asarray(axis, dtype=float)
    ax = ax / np.linalg.norm(ax)
    s = math.sin(angle / 2)
    return (math.cos(angle / 2), float(ax[0] * s), float(ax[1] * s), float(ax[2] * s))


def rotate(quat: Quat, vec: Vec3) -> NDArray[np.float64]:
    """Rotate ``vec`` by unit quaternion ``quat``."""
    out = np.zeros(3)
    mujoco.mju_rotVecQuat(out, np.asarray(vec, dtype=float), np.asarray(quat, dtype=float))
    return out


def set_env_collision(geom: mujoco.MjsGeom) -> None:
    geom.contype, geom.conaffinity = ENV_CONTYPE, ENV_CONAFFINITY


def set_robot_collision(geom: mujoco.MjsGeom) -> None:
    geom.contype, geom.conaffinity = ROBOT_CONTYPE, ROBOT_CONAFFINITY


def set_visual_only(geom: mujoco.MjsGeom) -> None:
    geom.contype, geom.conaffinity = 0, 0

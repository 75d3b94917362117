"""Rigid motions of the floor plane (x, y, yaw): how a segment moves with its object.

A segment recorded relative to an object's pose ``source`` is carried into a world where
the object rests at ``target`` by ``target * source^-1`` (:meth:`Planar.between`), applied
to the base's path and to every end-effector pose alike (positions turned about the world's
z axis, orientations turned by the same yaw, heights kept).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray


def wrap(angle: float) -> float:
    """``angle`` in [-pi, pi)."""
    return (angle + math.pi) % (2 * math.pi) - math.pi


@dataclass(frozen=True)
class Planar:
    """A pose on the floor, or the motion taking the origin there: x, y (m), yaw (rad)."""

    x: float = 0.0
    y: float = 0.0
    yaw: float = 0.0

    @staticmethod
    def of(pose: NDArray[np.float64]) -> Planar:
        """A pose array (x, y, yaw, ...) as a planar pose."""
        return Planar(float(pose[0]), float(pose[1]), float(pose[2]))

    @staticmethod
    def between(source: Planar, target: Planar) -> Planar:
        """The motion carrying ``source`` onto ``target``: ``target * source^-1``."""
        return target.compose(source.inverse())

    def compose(self, other: Planar) -> Planar:
        """``self * other``: ``other`` expressed in ``self``'s frame, in the world."""
        c, s = math.cos(self.yaw), math.sin(self.yaw)
        return Planar(
            self.x + c * other.x - s * other.y,
            self.y + s * other.x + c * other.y,
            wrap(self.yaw + other.yaw),
        )

    def scaled(self, fraction: float) -> Planar:
        """This motion's x, y and yaw times ``fraction`` (1: itself, 0: no motion), to ease
        from one into none."""
        return Planar(self.x * fraction, self.y * fraction, self.yaw * fraction)

    def inverse(self) -> Planar:
        c, s = math.cos(self.yaw), math.sin(self.yaw)
        return Planar(-(c * self.x + s * self.y), -(-s * self.x + c * self.y), -self.yaw)

    def poses(self, poses: NDArray[np.float64]) -> NDArray[np.float64]:
        """Planar poses (n, 3: x, y, yaw) moved by this motion."""
        c, s = math.cos(self.yaw), math.sin(self.yaw)
        out = np.empty_like(poses)
        out[:, 0] = self.x + c * poses[:, 0] - s * poses[:, 1]
        out[:, 1] = self.y + s * poses[:, 0] + c * poses[:, 1]
        out[:, 2] = poses[:, 2] + self.yaw
        return out

    def points(self, points: NDArray[np.float64]) -> NDArray[np.float64]:
        """Points (n, 3) moved by this motion (heights kept)."""
        c, s = math.cos(self.yaw), math.sin(self.yaw)
        out = points.copy()
        out[:, 0] = self.x + c * points[:, 0] - s * points[:, 1]
        out[:, 1] = self.y + s * points[:, 0] + c * points[:, 1]
        return out

    def quaternions(self, quats: NDArray[np.float64]) -> NDArray[np.float64]:
        """Orientations (n, 4: w, x, y, z) turned by this motion's yaw about the world z."""
        return yaw_times(self.yaw, quats)

    def as_dict(self) -> dict[str, float]:
        return {"x": round(self.x, 6), "y": round(self.y, 6), "yaw": round(self.yaw, 6)}


def yaw_times(yaw: float, quats: NDArray[np.float64]) -> NDArray[np.float64]:
    """``q_z(yaw) * q`` for each (w, x, y, z) row of ``quats``."""
    cw, sz = math.cos(yaw / 2), math.sin(yaw / 2)
    w, x, y, z = quats[:, 0], quats[:, 1], quats[:, 2], quats[:, 3]
    return np.stack([cw * w - sz * z, cw * x - sz * y, cw * y + sz * x, cw * z + sz * w], axis=1)


def yaw_of(quat: NDArray[np.float64] | tuple[float, ...]) -> float:
    """The heading of a (w, x, y, z) orientation about the world z axis."""
    w, x, y, z = (float(v) for v in quat)
    return math.atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))

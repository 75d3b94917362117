"""Holonomic base motion: a commanded twist, limited in speed and acceleration, integrated
into the reference pose the base's position actuators track."""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from workcell.control.command import BaseTwist
from workcell.sim.config import RobotConfig


class BaseMotion:
    def __init__(self, config: RobotConfig) -> None:
        self._config = config
        self.pose: NDArray[np.float64] = np.zeros(3)
        """Reference pose (x, y, yaw) in the world."""
        self.twist: NDArray[np.float64] = np.zeros(3)
        """Current limited twist (vx, vy, wz) in the base frame."""

    def reset(self, pose: tuple[float, float, float]) -> None:
        self.pose = np.array(pose, dtype=float)
        self.twist = np.zeros(3)

    def step(self, command: BaseTwist, dt: float) -> NDArray[np.float64]:
        """Advance by ``dt`` toward ``command``; returns the new reference pose."""
        c = self._config
        wanted = np.array([command.vx, command.vy, command.wz])
        linear = wanted[:2]
        speed = float(np.linalg.norm(linear))
        if speed > c.max_linear_speed:
            wanted[:2] = linear * (c.max_linear_speed / speed)
        wanted[2] = float(np.clip(wanted[2], -c.max_yaw_rate, c.max_yaw_rate))
        delta = wanted - self.twist
        max_linear = c.linear_accel * dt
        norm = float(np.linalg.norm(delta[:2]))
        if norm > max_linear:
            delta[:2] *= max_linear / norm
        delta[2] = float(np.clip(delta[2], -c.yaw_accel * dt, c.yaw_accel * dt))
        self.twist = self.twist + delta
        yaw = self.pose[2] + 0.5 * self.twist[2] * dt
        cos, sin = math.cos(yaw), math.sin(yaw)
        vx, vy = self.twist[0], self.twist[1]
        self.pose = self.pose + dt * np.array(
            [cos * vx - sin * vy, sin * vx + cos * vy, self.twist[2]]
        )
        return self.pose

    def limit_lead(self, measured: NDArray[np.float64], max_lead: float) -> None:
        """Keep the reference within ``max_lead`` of the measured pose (m and rad), so a
        blocked base does not wind up a reference that would later jump."""
        lead = self.pose - measured
        if np.any(np.abs(lead) > max_lead):
            self.pose = measured + np.clip(lead, -max_lead, max_lead)
            self.twist = np.zeros(3)

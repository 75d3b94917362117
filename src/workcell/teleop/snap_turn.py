"""Snap turns: the base turns by a fixed angle on one flick of the operator's stick.

A comfort option for the headset (the client blacks the view out while the base turns, so
the operator never sees the world rotate). The turn is carried out here, on the sim clock,
not timed by the client: it steers the base's *reference* heading (which the base's
position actuators track, a moment behind) at full yaw rate, then along the braking curve
``w = sqrt(2 a left)`` of the robot's angular acceleration limit, so that the reference
comes to rest exactly at the angle and the base settles there. The client's frame rate and
the link's gaps do not change the angle.
"""

from __future__ import annotations

import math

SNAP_ANGLE = math.pi / 6
"""How far one snap turns the base (radians)."""
DONE_WITHIN = 1e-3
"""The snap is over once the reference heading is this close to its end (rad)..."""
STILL_YAW_RATE = 0.05
"""...and turns slower than this (rad/s)."""


class SnapTurn:
    """One snap under way: ``direction`` +1 turns left (counter-clockwise), -1 right, from
    the reference heading ``start_yaw``."""

    def __init__(self, direction: int, start_yaw: float, angle: float = SNAP_ANGLE) -> None:
        self.direction = 1 if direction > 0 else -1
        self.start_yaw = start_yaw
        self.angle = angle

    def yaw_rate(self, yaw: float, rate: float, max_rate: float, accel: float) -> float | None:
        """The yaw rate to command now, from the reference heading ``yaw`` and its yaw rate
        ``rate``; None once the turn is over."""
        turned = math.atan2(math.sin(yaw - self.start_yaw), math.cos(yaw - self.start_yaw))
        left = self.angle - turned * self.direction
        if left <= DONE_WITHIN and abs(rate) < STILL_YAW_RATE:
            return None
        return self.direction * min(max_rate, math.sqrt(2 * accel * max(0.0, left)))

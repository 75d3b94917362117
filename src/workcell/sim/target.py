"""The target zone on the table (``world.target``): where a trial's task may want a box at
rest. A task's scene may count a released box resting inside it as done (box transfer's
does), or read only its centre and size."""

from __future__ import annotations

import mujoco
import numpy as np

from workcell.sim.boxes import BoxPool, BoxSlot
from workcell.sim.config import WorldConfig

REST_SPEED = 0.05
"""A box moving slower than this (m/s) is at rest."""
HEIGHT_TOLERANCE = 0.03


class TargetZone:
    def __init__(self, config: WorldConfig) -> None:
        t = config.target
        self._table_height = t.table_height
        self.half = np.array(t.zone) / 2
        self.center = np.array(t.center)
        self.rest_z = t.table_height + config.box.size[2] / 2

    def place(self, center: tuple[float, float], box_height: float) -> None:
        """This trial's zone centre and the height at which its boxes rest in it."""
        self.center = np.array(center)
        self.rest_z = self._table_height + box_height / 2

    def contains(self, position: np.ndarray) -> bool:
        inside = bool(np.all(np.abs(position[:2] - self.center) <= self.half))
        return inside and abs(float(position[2]) - self.rest_z) <= HEIGHT_TOLERANCE

    def rests_in(
        self, data: mujoco.MjData, pool: BoxPool, slot: BoxSlot, held: BoxSlot | None
    ) -> bool:
        """True when ``slot`` rests in the zone and the robot no longer holds it."""
        if slot is held:
            return False
        return self.contains(pool.position(data, slot)) and pool.speed(data, slot) < REST_SPEED

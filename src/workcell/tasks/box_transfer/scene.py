"""Box transfer's part of the world: the delivery, watched each control period.

A released box that has come to rest inside the delivery zone on the table top, no longer
held, is delivered (:class:`~workcell.sim.target.TargetZone`), and taken away (parked) a
second later so the table stays clear. The table and its zone are the shared factory's
(:mod:`workcell.sim.arena`); box transfer adds no element of its own.
"""

from __future__ import annotations

import mujoco
import numpy as np

from workcell.sim.boxes import BoxState
from workcell.sim.config import WorldConfig
from workcell.sim.events import BoxCompleted, WorldEvent
from workcell.sim.world import World

DELIVERED_CLEAR_S = 1.0
"""A delivered box is taken away (parked) this long after delivery."""


class BoxTransferScene:
    """Delivers boxes that rest in the zone, and clears them from the table; the scene of
    the task named ``task_name``."""

    def __init__(self, task_name: str) -> None:
        self.task_name = task_name

    def build(self, spec: mujoco.MjSpec, config: WorldConfig) -> None:
        """Nothing to add: the conveyor, the table and its zone are the factory's."""

    def reset(self, world: World, rng: np.random.Generator) -> None:
        """Nothing to set: the feeder brings the boxes."""

    def watch(self, world: World, t: float) -> list[WorldEvent]:
        events: list[WorldEvent] = []
        held = world.grasp.holding
        boxes, data = world.boxes, world.data
        for slot in boxes.slots:
            if slot.state is BoxState.ACTIVE:
                if world.zone.rests_in(data, boxes, slot, held):
                    slot.state = BoxState.DELIVERED
                    slot.delivered_at = t
                    events.append(BoxCompleted(t, slot.index))
            elif slot.state is BoxState.DELIVERED and t - slot.delivered_at >= DELIVERED_CLEAR_S:
                boxes.park(data, slot)
        return events

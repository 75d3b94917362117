"""Shelve's part of the world: the shelf unit, and one box waiting on the table.

The box starts on the delivery table of the shared factory (here the pick table, moved by
``randomization.target_shift`` like the zone), near its edge facing -y (the side the robot
comes from), turned so that its grasp axis runs along x; the feeder brings nothing
(:meth:`World.hold_feeder`). Each trial draws which board it asks for and where the shelf
stands (:class:`~workcell.tasks.shelve.shelf.ShelfLayout`), recorded with the trial's
conditions under ``task``.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np
from numpy.typing import NDArray

from workcell.sim.config import WorldConfig
from workcell.sim.events import WorldEvent
from workcell.sim.world import World
from workcell.tasks.shelve.shelf import ShelfLayout, build_shelf, place_shelf

PICK_HEADING = math.pi / 2
"""The way the robot faces to pick the box up: toward +y, the table's near side."""
PICK_INSET = 0.15
"""How far (m) from the table's centre toward the robot's side the box starts."""
PICK_JITTER = 0.04
"""The box starts up to this far (m) either way along x, and ..."""
PICK_YAW_JITTER = 0.15
"""... turned up to this much (rad) either way."""


def box_start(world: World, rng: np.random.Generator) -> tuple[NDArray[np.float64], float]:
    """Where the trial's box starts (its centre) and its yaw."""
    cx, cy = world.conditions.target_center
    height = world.config.target.table_height + world.conditions.box_size[2] / 2 + 0.002
    x = cx + float(rng.uniform(-PICK_JITTER, PICK_JITTER))
    yaw = PICK_HEADING + float(rng.uniform(-PICK_YAW_JITTER, PICK_YAW_JITTER))
    return np.array([x, cy - PICK_INSET, height]), yaw


class ShelveScene:
    """Adds the shelf; each reset sets one box on the table and draws the asked board."""

    def __init__(self, task_name: str) -> None:
        self.task_name = task_name

    def build(self, spec: mujoco.MjSpec, config: WorldConfig) -> None:
        build_shelf(spec)

    def reset(self, world: World, rng: np.random.Generator) -> None:
        world.hold_feeder()
        layout = ShelfLayout.draw(rng, world.config.randomization.target_shift)
        place_shelf(world.model, layout)
        world.conditions = world.conditions.with_task(layout.recorded())
        position, yaw = box_start(world, rng)
        data = world.data
        slot = world.boxes.release(data, 0.0)
        assert slot is not None, "the pool has a box at every reset"
        data.qpos[slot.qpos : slot.qpos + 3] = position
        data.qpos[slot.qpos + 3 : slot.qpos + 7] = (math.cos(yaw / 2), 0, 0, math.sin(yaw / 2))

    def watch(self, world: World, t: float) -> list[WorldEvent]:
        """Nothing to watch: the judge reads the box on the shelf from the world."""
        return []

"""Palletize's part of the world: the pallet with its four slot marks, set for each trial,
and the boxes placed in its slots, watched each control period.

A released box resting in a slot, no longer held, is placed (:class:`BoxCompleted`, its
state ``DELIVERED``: the floor's clean-up leaves it alone); a placed box that leaves its
slot again (knocked off, picked up) is active again. Placed boxes stay on the pallet.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np

from workcell.sim.boxes import BoxState
from workcell.sim.config import WorldConfig
from workcell.sim.events import BoxCompleted, WorldEvent
from workcell.sim.spec_utils import set_env_collision, set_visual_only
from workcell.sim.world import World
from workcell.tasks.palletize.layout import (
    PALLET_CENTER,
    PALLET_HEIGHT,
    SLOT_SIGNS,
    SLOT_TOLERANCE,
    PalletLayout,
    pallet_half_size,
)

BOX = mujoco.mjtGeom.mjGEOM_BOX
PALLET = "pallet"
PALLET_TOP = "pallet_top"
REST_SPEED = 0.05
"""A box moving slower than this (m/s) is at rest."""
WOOD_RGBA = (0.72, 0.56, 0.36, 1.0)
SLOT_RGBA = (0.2, 0.75, 0.35, 0.6)
MARK_THICKNESS = 0.001


def slot_mark(index: int) -> str:
    return f"pallet_slot_{index}"


def resting(world: World, box_index: int) -> bool:
    """Box ``box_index`` is at rest and no gripper holds it."""
    boxes = world.boxes
    slot = boxes.slots[box_index]
    return world.grasp.holding is not slot and boxes.speed(world.data, slot) < REST_SPEED


class PalletizeScene:
    """Adds the pallet to the factory, places it for each trial, watches its slots."""

    def __init__(self, task_name: str) -> None:
        self.task_name = task_name
        self.layout: PalletLayout | None = None
        """The current trial's pallet (set at each reset)."""

    def build(self, spec: mujoco.MjSpec, config: WorldConfig) -> None:
        """The pallet: a wooden platform on the floor (it collides), with four flat
        visual marks on its top, one per slot, laid out at each reset."""
        hx, hy = pallet_half_size(config)
        pallet = spec.worldbody.add_body(name=PALLET, pos=[*PALLET_CENTER, 0.0])
        top = pallet.add_geom(
            name=PALLET_TOP,
            type=BOX,
            size=[hx, hy, PALLET_HEIGHT / 2],
            pos=[0, 0, PALLET_HEIGHT / 2],
            rgba=list(WOOD_RGBA),
            material="cardboard",
            friction=[1.0, 0.005, 0.0001],
        )
        set_env_collision(top)
        for index in range(len(SLOT_SIGNS)):
            mark = pallet.add_geom(
                name=slot_mark(index),
                type=BOX,
                size=[0.1, 0.1, MARK_THICKNESS],
                pos=[0, 0, PALLET_HEIGHT + MARK_THICKNESS],
                rgba=list(SLOT_RGBA),
            )
            set_visual_only(mark)

    def reset(self, world: World, rng: np.random.Generator) -> None:
        """The pallet where this trial's conditions put it, its slots laid out for this
        trial's boxes (nothing is drawn here: the layout follows the drawn conditions)."""
        layout = PalletLayout.of(world.conditions.as_dict(), world.config)
        self.layout = layout
        model = world.model
        body = model.body(PALLET).id
        model.body_pos[body] = (*layout.center, 0.0)
        model.body_quat[body] = (math.cos(layout.yaw / 2), 0.0, 0.0, math.sin(layout.yaw / 2))
        for index in range(len(SLOT_SIGNS)):
            geom = model.geom(slot_mark(index)).id
            sx, sy = layout.slot_local(index)
            model.geom_pos[geom] = (sx, sy, PALLET_HEIGHT + MARK_THICKNESS)
            half = (
                layout.size[0] / 2 + SLOT_TOLERANCE,
                layout.size[1] / 2 + SLOT_TOLERANCE,
                MARK_THICKNESS,
            )
            model.geom_size[geom] = half
            model.geom_rbound[geom] = float(np.linalg.norm(half))

    def watch(self, world: World, t: float) -> list[WorldEvent]:
        layout = self.layout
        if layout is None:
            return []
        events: list[WorldEvent] = []
        boxes, data = world.boxes, world.data
        for slot in boxes.slots:
            if slot.state is BoxState.PARKED:
                continue
            in_slot = layout.slot_of(boxes.position(data, slot)) is not None
            if slot.state is BoxState.ACTIVE and in_slot and resting(world, slot.index):
                slot.state = BoxState.DELIVERED
                slot.delivered_at = t
                events.append(BoxCompleted(t, slot.index))
            elif slot.state is BoxState.DELIVERED and (not in_slot or world.grasp.holding is slot):
                slot.state = BoxState.ACTIVE
        return events

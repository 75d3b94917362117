"""Sort's part of the world: a second table (the sorting table) beside the factory's
delivery table, each pooled box given its kind's sides, mass and colour at every reset, and
the sorting watched each control period.

A box that rests released in its own kind's zone for :data:`SORTED_S` is sorted (a
``BoxCompleted`` event) and taken away for the rest of the trial (the feeder brings the
pool's other boxes; once every box has been sorted the pool is refilled in the same order).
A box that rests as long in the other kind's zone is missorted: it stays where it is, and
the trial has failed.
"""

from __future__ import annotations

import mujoco
import numpy as np

from workcell.errors import ConfigError, Problem
from workcell.sim.arena import SAFETY_RGBA, add_zone_table
from workcell.sim.boxes import BoxSlot, BoxState
from workcell.sim.conditions import shape_box
from workcell.sim.config import WorldConfig
from workcell.sim.events import BoxCompleted, WorldEvent
from workcell.sim.looks import add_decor
from workcell.sim.target import HEIGHT_TOLERANCE, REST_SPEED
from workcell.sim.world import World
from workcell.tasks.sort.layout import SortLayout, sorting_table_center

SORTED_S = 1.0
"""How long a released box must rest in a zone to count as set down there."""
TABLE_BODY = "sorting_table"
ZONE_GEOM = "sorting_table_zone"
DELIVERY_ZONE_GEOM = "target_zone"
ZONE_ALPHA = 0.6
CLEARANCE_M = 0.3
"""How far the sorting table's zone keeps from the conveyor and the delivery table's zone
(plus each one's shift)."""
BOX = mujoco.mjtGeom.mjGEOM_BOX


class SortScene:
    """The sorting table, the boxes' kinds and the sorting; the scene of ``task_name``."""

    def __init__(self, task_name: str) -> None:
        self.task_name = task_name
        self._layout: SortLayout | None = None
        self.missorted: set[int] = set()
        """Pool indices of the boxes set down in the other kind's zone this trial."""
        self.sorted_count = 0
        """How many boxes this trial sorted (each then taken away)."""
        self._resting: dict[int, tuple[int, float]] = {}

    @property
    def layout(self) -> SortLayout:
        """This trial's layout (drawn at the world's reset)."""
        if self._layout is None:
            raise RuntimeError("the sort scene has no layout before the world's first reset")
        return self._layout

    def build(self, spec: mujoco.MjSpec, config: WorldConfig) -> None:
        """The sorting table: the delivery table's twin across the conveyor."""
        _check_room(config)
        table = add_zone_table(
            spec,
            config,
            center=sorting_table_center(config),
            body=TABLE_BODY,
            top="sorting_table_top",
            zone=ZONE_GEOM,
            zone_rgba=(0.5, 0.5, 0.5, ZONE_ALPHA),
        )
        _add_keep_clear_frame(table, config)

    def reset(self, world: World, rng: np.random.Generator) -> None:
        """Draw the trial's layout, move the sorting table, give each pooled box its kind
        and tint each zone with its kind's colour; the layout is recorded with the trial's
        conditions."""
        layout = SortLayout.draw(world.config, world.conditions, rng)
        self._layout = layout
        self.missorted = set()
        self.sorted_count = 0
        self._resting = {}
        model, data = world.model, world.data
        model.body_pos[model.body(TABLE_BODY).id, :2] = layout.tables[1]
        for slot in world.boxes.slots:
            kind = layout.kinds[layout.kind_of(slot.index)]
            shape_box(model, slot, kind.size, kind.mass, kind.rgba)
            slot.size = kind.size
        for geom, kind in ((DELIVERY_ZONE_GEOM, layout.kinds[0]), (ZONE_GEOM, layout.kinds[1])):
            model.geom_rgba[model.geom(geom).id] = (*kind.rgba[:3], ZONE_ALPHA)
        # mj_setConst computes the derived constants at qpos0, overwriting the start state.
        qpos, qvel = data.qpos.copy(), data.qvel.copy()
        mujoco.mj_setConst(model, data)
        data.qpos[:], data.qvel[:] = qpos, qvel
        world.conditions = world.conditions.with_task(layout.recorded())

    def watch(self, world: World, t: float) -> list[WorldEvent]:
        layout = self.layout
        events: list[WorldEvent] = []
        boxes, data = world.boxes, world.data
        for slot in boxes.active():
            table = resting_table(world, layout, slot)
            if table is None:
                self._resting.pop(slot.index, None)
                continue
            since = self._resting.setdefault(slot.index, (table, t))
            if since[0] != table:
                self._resting[slot.index] = (table, t)
                continue
            if t - since[1] + 1e-9 < SORTED_S:
                continue
            if table == layout.kind_of(slot.index):
                boxes.park(data, slot)
                slot.state = BoxState.DELIVERED  # taken away: not fed again this round
                slot.delivered_at = t
                del self._resting[slot.index]
                self.sorted_count += 1
                events.append(BoxCompleted(t, slot.index))
            else:
                self.missorted.add(slot.index)
        if all(slot.state is BoxState.DELIVERED for slot in boxes.slots):
            for slot in boxes.slots:
                slot.state = BoxState.PARKED
        return events


def resting_table(world: World, layout: SortLayout, slot: BoxSlot) -> int | None:
    """The table (0: the delivery table, 1: the sorting table) in whose zone ``slot``'s box
    rests released on the top, or None."""
    if world.grasp.holding is slot:
        return None
    boxes = world.boxes
    if boxes.speed(world.data, slot) >= REST_SPEED:
        return None
    table = zone_under(world.config, layout, boxes.position(world.data, slot))
    if table is None:
        return None
    rest_z = world.config.target.table_height + boxes.size_of(slot)[2] / 2
    z = float(boxes.position(world.data, slot)[2])
    return table if abs(z - rest_z) <= HEIGHT_TOLERANCE else None


def zone_under(config: WorldConfig, layout: SortLayout, position: np.ndarray) -> int | None:
    """The table whose zone's rectangle holds ``position``'s x, y, or None."""
    half = np.array(config.target.zone) / 2
    for table, center in enumerate(layout.tables):
        if bool(np.all(np.abs(position[:2] - np.array(center)) <= half)):
            return table
    return None


def _add_keep_clear_frame(table: mujoco.MjsBody, config: WorldConfig) -> None:
    """The safety-yellow floor frame around the table, as the delivery table has
    (:func:`workcell.sim.arena.build_arena`), moving with it."""
    t, line, margin = config.target, 0.04, 0.25
    hx, hy = t.zone[0] / 2 + 0.05 + margin, t.zone[1] / 2 + 0.05 + margin
    sides = (
        (0.0, -hy, hx + line, line / 2),
        (0.0, hy, hx + line, line / 2),
        (-hx, 0.0, line / 2, hy),
        (hx, 0.0, line / 2, hy),
    )
    for i, (cx, cy, sx, sy) in enumerate(sides):
        add_decor(
            table,
            f"sorting_table_line_{i}",
            BOX,
            [sx, sy, 0.001],
            rgba=SAFETY_RGBA,
            material="floor_paint",
            pos=[cx, cy, 0.002],
        )


def _check_room(config: WorldConfig) -> None:
    """The sorting table must keep clear of the conveyor and of the delivery table."""
    t, c, shift = config.target, config.conveyor, config.randomization.target_shift
    x, y = sorting_table_center(config)
    half_x, half_y = t.zone[0] / 2, t.zone[1] / 2
    margin = CLEARANCE_M + shift
    beside_belt = c.start_x - margin - half_x <= x <= c.end_x + margin + half_x
    across_belt = abs(y - c.center_y) <= c.width / 2 + margin + half_y
    apart_x = abs(x - t.center[0]) >= 2 * half_x + CLEARANCE_M + 2 * shift
    apart_y = abs(y - t.center[1]) >= 2 * half_y + CLEARANCE_M + 2 * shift
    problems: list[Problem] = []
    if beside_belt and across_belt:
        problems.append(
            Problem(
                "world.target.center",
                t.center,
                "for sort, the delivery table mirrored across the conveyor (the sorting "
                f"table, at {x:g}, {y:g}) must keep {CLEARANCE_M:g} m (+ target_shift) clear "
                "of the conveyor",
            )
        )
    if not (apart_x or apart_y):
        problems.append(
            Problem(
                "world.target.center",
                t.center,
                "for sort, the delivery table must stand far enough from the conveyor's "
                f"centre line that its mirror image (the sorting table, at {x:g}, {y:g}) "
                f"keeps {CLEARANCE_M:g} m (+ twice target_shift) from it",
            )
        )
    if problems:
        raise ConfigError(problems)

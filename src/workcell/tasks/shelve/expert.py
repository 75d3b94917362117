"""Shelve's expert: box transfer's, picking the box off the table and raising it to the
asked board's height before it drives to the shelf.

It overrides where a box is found (:meth:`ShelveExpert._resting_box`: on the pick table),
how it is approached (:meth:`ShelveExpert._approach`: from the table's near side), where it
goes (:meth:`ShelveExpert.placement`: the asked board) and the carry, which first brings
the box to just above that board (the IK raises the spine and the arms for the top board),
so the box travels in over the board and is set down on it.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from workcell.control.command import BaseTwist
from workcell.expert.grasp_geometry import PalmTargets
from workcell.expert.phase import ExpertPhase
from workcell.sim.boxes import BoxSlot
from workcell.sim.world import World
from workcell.tasks.elements.expert import ExpertOperator, Placement
from workcell.tasks.shelve.scene import PICK_HEADING
from workcell.tasks.shelve.shelf import ShelfLayout
from workcell.tasks.shelve.stages import REST_SPEED

CLEARANCE_M = 0.06
"""How far above the asked board's top the box's bottom travels in."""
RAISE_STEP_M = 0.004
"""How far the palms move up or down in one control period while raising the box."""
STRAIGHT_IN_M = 0.5
"""The last stretch (m) to the shelf is driven straight in, square to its front, so the
box never sweeps over a neighbouring board."""
WINDUP_M = 0.03
"""While setting the box down, each palm's target stays this close (m) to where the palm is:
a box that meets the board before the hands expect it (it tilts in a grasp of friction
alone) stops the hands instead of leaving their targets to run on into the board, from
where letting go would drag the box off again."""
SHELF_STAND_M = 0.65
"""How far from the asked board's centre the base stops: the box lands at the board's
centre within the arms' reach."""


class ShelveExpert(ExpertOperator):
    """Puts the box from the table on the asked board."""

    place_distance = SHELF_STAND_M

    def placement(self, world: World, box: BoxSlot) -> Placement:
        layout = ShelfLayout.from_recorded(world.conditions.task_values)
        rest_z = layout.board_top(layout.asked) + world.conditions.box_size[2] / 2
        return Placement(layout.board_center(layout.asked), rest_z)

    def _resting_box(self, world: World) -> BoxSlot | None:
        """A box at rest on the pick table (the delivery table of the factory)."""
        table = world.config.target.table_height + world.conditions.box_size[2] / 2
        cx, cy = world.conditions.target_center
        half = np.array(world.config.target.zone) / 2 + 0.05
        for slot in world.boxes.active():
            pos = world.boxes.position(world.data, slot)
            on_table = abs(pos[2] - table) < 0.03 and bool(
                np.all(np.abs(pos[:2] - (cx, cy)) <= half)
            )
            if on_table and world.boxes.speed(world.data, slot) < REST_SPEED:
                return slot
        return None

    def _pick_heading(self, world: World) -> float:
        return PICK_HEADING

    def _carry_route(self, world: World) -> list[NDArray[np.float64]]:
        route = super()._carry_route(world)
        goal = route[-1]
        heading = np.array([math.cos(goal[2]), math.sin(goal[2])])
        before = goal.copy()
        before[:2] -= heading * STRAIGHT_IN_M
        return [*route[:-1], before, goal]

    def _place(self, world: World) -> BaseTwist:
        twist = super()._place(world)
        palms = self._palms
        if self.phase is ExpertPhase.PLACE and palms is not None:
            here = [world.to_base_frame(world.tcp_pose(side)[0]) for side in ("l", "r")]
            near = [
                at + np.clip(target - at, -WINDUP_M, WINDUP_M)
                for at, target in zip(
                    here, (palms.left_position, palms.right_position), strict=True
                )
            ]
            self._palms = PalmTargets(
                near[0], palms.left_quaternion, near[1], palms.right_quaternion
            )
        return twist

    def _carry(self, world: World) -> BaseTwist:
        """Bring the box to the asked board's height (standing still), then carry it."""
        if self._lost_box(world):
            return BaseTwist()
        box = self._require_box()
        assert self._palms is not None
        place = self.placement(world, box)
        carry_z = place.rest_z + CLEARANCE_M
        delta = carry_z - float(world.boxes.position(world.data, box)[2])
        if abs(delta) > 0.01:
            step = float(np.clip(delta, -RAISE_STEP_M, RAISE_STEP_M))
            self._palms = self._palms.shifted(np.array([0.0, 0.0, step]))
            if not self._timed_out(world, 6.0):
                return BaseTwist()
        return super()._carry(world)

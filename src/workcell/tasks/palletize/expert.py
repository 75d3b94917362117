"""Palletize's expert: box transfer's expert (:class:`ExpertOperator`), whose boxes go to
the pallet's next free slot, each set down from the pallet side its row faces, with the
base driven around the pallet on the way there and back.

Slots fill in :data:`~workcell.tasks.palletize.layout.SLOT_SIGNS` order. The base stops
square-on to the slot's row, close enough for the arms to set the box on the slot's
centre (:data:`BASE_CLEARANCE` from the pallet's edge), after a waypoint
:data:`SIDE_CLEARANCE` off the pallet's conveyor side, and comes back by the same
waypoint before it turns to the conveyor again.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from workcell.control.command import BaseTwist
from workcell.expert.grasp_geometry import PalmTargets
from workcell.expert.phase import ExpertPhase
from workcell.sim.boxes import BoxSlot, BoxState
from workcell.sim.world import World
from workcell.tasks.elements.base_drive import wrap_angle
from workcell.tasks.elements.expert import STANDBY_DISTANCE, ExpertOperator, Placement
from workcell.tasks.palletize.judge import filled_slots
from workcell.tasks.palletize.layout import EDGE_MARGIN, SLOT_SIGNS, PalletLayout

BASE_FRONT = 0.33
"""From the base's centre to its front bumper (m)."""
BASE_CLEARANCE = 0.06
"""Between the base's front and the pallet's edge when it sets a box down (m)."""
STAND_OFF = BASE_FRONT + BASE_CLEARANCE
"""From the pallet's edge to the base's centre as it sets a box down (m)."""
SIDE_CLEARANCE = 0.6
"""How far off the pallet's +y side (toward the conveyor) the base passes (m)."""
BACK_OFF_M = 0.4
"""How far the base backs straight away from the pallet once a box is set down (m)."""
RELEASE_GAP = 0.04
"""How far each palm moves out from the box's side as it lets go (m): little, since the
hand behind the pad reaches about 0.2 m further out, toward the box beside it in the row."""
RELEASE_LIFT_SPEED = 0.25
"""How fast the open palms rise past the box's top before the base backs off (m/s)."""
RELEASE_S = 1.6
"""How long letting go takes, from opening the grippers to backing off (s)."""


class PalletizeExpert(ExpertOperator):
    """Fills the pallet's slots one box at a time."""

    def start_trial(self, trial_seed: int) -> None:
        super().start_trial(trial_seed)
        self._slot: int | None = None
        self._opened: PalmTargets | None = None

    def placement(self, world: World, box: BoxSlot) -> Placement:
        layout = _layout(world)
        if self._slot is None:
            self._slot = _next_free_slot(world, layout)
        return Placement(layout.slot_center(self._slot), layout.rest_z)

    def _release(self, world: World) -> BaseTwist:
        """Open, move each palm straight out from the box's side, then raise the open
        palms past its top: the box is never dragged along the pads (the palms' centre
        need not be the box's), and the hands never reach toward the box beside it."""
        self._close = 0.0
        elapsed = world.time - self._phase_start
        if elapsed > 0.3 and self._palms is not None:
            if self._opened is None:
                self._opened = _opened(self._palms, RELEASE_GAP)
            lift = (elapsed - 0.3) * RELEASE_LIFT_SPEED
            self._palms = self._opened.shifted(np.array([0.0, 0.0, lift]))
        if elapsed > RELEASE_S:
            self._opened = None
            if self._require_box().state is BoxState.DELIVERED:
                self.deliveries += 1
            self._enter(world, ExpertPhase.BACKOFF)
        return BaseTwist()

    # --- routes around the pallet ---------------------------------------------------------

    def _carry_route(self, world: World) -> list[NDArray[np.float64]]:
        layout = _layout(world)
        self._slot = _next_free_slot(world, layout)
        sign = SLOT_SIGNS[self._slot][0]
        heading = layout.yaw if sign < 0 else layout.yaw + math.pi
        heading = float(world.base_pose[2]) + wrap_angle(heading - float(world.base_pose[2]))
        slot_x, slot_y = layout.slot_local(self._slot)
        stand_x = slot_x + sign * (layout.size[0] / 2 + EDGE_MARGIN + STAND_OFF)
        side = layout.to_world(np.array([stand_x, layout.half[1] + SIDE_CLEARANCE]))
        goal = layout.to_world(np.array([stand_x, slot_y]))
        return [np.array([*side, heading]), np.array([*goal, heading])]

    def _backoff(self, world: World) -> BaseTwist:
        if self.phase is ExpertPhase.BACKOFF and not self._waypoints:
            self._waypoints = self._return_route(world)
        self._close = 0.0
        if self._palms is not None:
            self._palms = self._palms.shifted(np.array([0.0, 0.0, 0.004]))
        goal = self._waypoints[0]
        twist = self._drive(world, goal, tolerance=0.05)
        if self._arrived(world, goal, tolerance=0.05 if len(self._waypoints) == 1 else 0.1):
            self._waypoints.pop(0)
        if not self._waypoints or self._timed_out(world, 12.0):
            self._waypoints = []
            self._box = None
            self._slot = None
            self._grasp_attempts = 0
            self._enter(world, ExpertPhase.WAIT)
        return twist

    def _return_route(self, world: World) -> list[NDArray[np.float64]]:
        """Straight back, then (beside the pallet) out to its conveyor side."""
        pose = world.base_pose
        back = np.array([math.cos(pose[2]), math.sin(pose[2])])
        first = pose.copy()
        first[:2] -= back * BACK_OFF_M
        route = [first]
        layout = _layout(world)
        local = layout.to_local(first[:2])
        beside = abs(local[1]) < layout.half[1] + SIDE_CLEARANCE - 0.05
        if beside:
            side = layout.to_world(np.array([local[0], layout.half[1] + SIDE_CLEARANCE]))
            route.append(np.array([*side, pose[2]]))
        # Face the conveyor before waiting: a base that turns as it drives to a box on the
        # belt sweeps the boxes queued there.
        c = world.config.conveyor
        heading = c.direction_yaw + math.pi
        heading = float(pose[2]) + wrap_angle(heading - float(pose[2]))
        route.append(np.array([c.end_x + STANDBY_DISTANCE, c.center_y, heading]))
        return route


def _opened(palms: PalmTargets, gap: float) -> PalmTargets:
    """``palms`` each moved ``gap`` straight out, away from the other."""
    axis = palms.left_position - palms.right_position
    axis = axis / max(float(np.linalg.norm(axis)), 1e-9)
    return PalmTargets(
        palms.left_position + axis * gap,
        palms.left_quaternion,
        palms.right_position - axis * gap,
        palms.right_quaternion,
    )


def _layout(world: World) -> PalletLayout:
    return PalletLayout.of(world.conditions.as_dict(), world.config)


def _next_free_slot(world: World, layout: PalletLayout) -> int:
    filled = filled_slots(world, layout)
    return next((i for i in range(len(SLOT_SIGNS)) if i not in filled), len(SLOT_SIGNS) - 1)

"""Judging a shelve trial as it runs: success once the box has rested on the asked board,
released and still, for a whole second of sim time (never one transient frame)."""

from __future__ import annotations

from workcell.sim.boxes import BoxSlot
from workcell.sim.events import WorldEvent
from workcell.sim.world import World
from workcell.tasks.shelve.shelf import ShelfLayout
from workcell.tasks.shelve.stages import (
    LIFT_M,
    REST_SPEED,
    SETTLE_S,
    SHELVE_STAGES,
    ShelveStage,
)
from workcell.tasks.task import Evaluation


def resting_on_asked_board(world: World, layout: ShelfLayout) -> BoxSlot | None:
    """The box resting on the asked board, released, untouched and still (None: none)."""
    grasp = world.grasp
    if grasp.holding is not None:
        return None
    height = world.conditions.box_size[2]
    for slot in world.boxes.active():
        if slot is grasp.contact_l or slot is grasp.contact_r:
            continue
        position = world.boxes.position(world.data, slot)
        still = world.boxes.speed(world.data, slot) < REST_SPEED
        if still and layout.on_board(layout.asked, position, height):
            return slot
    return None


class ShelveJudge:
    """One shelve trial: the furthest stage reached and how long the box has rested."""

    def __init__(self) -> None:
        self.stage: ShelveStage = "none"
        self._hold_start: tuple[int, float] | None = None
        self._resting_since: float | None = None

    @property
    def done(self) -> int:
        return int(self.stage == "settled")

    def observe(self, event: WorldEvent) -> None:
        """Nothing in the world's events decides it: the judge reads the world."""

    def evaluate(self, world: World) -> Evaluation:
        grasp = world.grasp
        if grasp.contact_l is not None or grasp.contact_r is not None:
            self._reach("touched")
        held = grasp.holding
        if held is None:
            self._hold_start = None
        else:
            self._reach("grasped")
            z = float(world.boxes.position(world.data, held)[2])
            if self._hold_start is None or self._hold_start[0] != held.index:
                self._hold_start = (held.index, z)
            if z - self._hold_start[1] >= LIFT_M:
                self._reach("lifted")
        layout = ShelfLayout.from_recorded(world.conditions.task_values)
        if resting_on_asked_board(world, layout) is None:
            self._resting_since = None
        else:
            self._reach("placed")
            if self._resting_since is None:
                self._resting_since = world.time
            if world.time - self._resting_since >= SETTLE_S - 1e-9:
                self._reach("settled")
        success = self.stage == "settled"
        progress = SHELVE_STAGES.index(self.stage) / (len(SHELVE_STAGES) - 1)
        return Evaluation(success=success, failure=False, progress=progress, stage=self.stage)

    def _reach(self, stage: ShelveStage) -> None:
        if SHELVE_STAGES.index(stage) > SHELVE_STAGES.index(self.stage):
            self.stage = stage

"""Judging a palletize trial as it runs: read from the world at each frame instant.

Success is a settled pallet: its four slots each hold a different box, at rest and
released, with no box in the grippers, for :data:`~workcell.tasks.palletize.stages.SETTLE_S`
without a break (on the world's clock). A full pallet at one frame instant is ``placed_4``,
not success; a box knocked out of its slot breaks the count and the settling starts again.
"""

from __future__ import annotations

from workcell.sim.boxes import BoxState
from workcell.sim.events import WorldEvent
from workcell.sim.world import World
from workcell.tasks.palletize.layout import PalletLayout
from workcell.tasks.palletize.scene import resting
from workcell.tasks.palletize.stages import PALLET_BOXES, SETTLE_S, stage_of
from workcell.tasks.task import Evaluation


def filled_slots(world: World, layout: PalletLayout) -> dict[int, int]:
    """The slots that hold a box at rest and released now: slot index to box index (one
    box a slot; a slot with two boxes in it counts once)."""
    filled: dict[int, int] = {}
    boxes = world.boxes
    for box in boxes.slots:
        if box.state is BoxState.PARKED:
            continue
        slot = layout.slot_of(boxes.position(world.data, box))
        if slot is not None and slot not in filled and resting(world, box.index):
            filled[slot] = box.index
    return filled


class PalletizeJudge:
    """A trial that must fill the pallet's four slots, one box in each."""

    def __init__(self, required: int = PALLET_BOXES) -> None:
        self.required = required
        self._filled = 0
        self._most = 0
        self._touched = False
        self._grasped = False
        self._full_since: float | None = None
        self._reached_settled = False

    @property
    def done(self) -> int:
        """Slots filled at the latest frame instant."""
        return self._filled

    def observe(self, event: WorldEvent) -> None:
        """Nothing in the world's events decides it: the judge reads the world."""

    def evaluate(self, world: World) -> Evaluation:
        grasp = world.grasp
        if grasp.contact_l is not None or grasp.contact_r is not None:
            self._touched = True
        if grasp.holding is not None:
            self._grasped = True
        layout = PalletLayout.of(world.conditions.as_dict(), world.config)
        self._filled = len(filled_slots(world, layout))
        self._most = max(self._most, self._filled)
        full = self._filled >= self.required and grasp.holding is None
        if not full:
            self._full_since = None
        elif self._full_since is None:
            self._full_since = world.time
        settled = self._full_since is not None and world.time - self._full_since >= SETTLE_S - 1e-9
        self._reached_settled = self._reached_settled or settled
        return Evaluation(
            success=settled,
            failure=False,
            progress=min(1.0, self._filled / self.required),
            stage=stage_of(self._touched, self._grasped, self._most, self._reached_settled),
        )

"""Palletize's settled check: each box the full pallet held stays in its slot.

Data generation runs the simulation on for a second after a success
(:mod:`workcell.generate.recheck`) and asks each control period whether every box that
filled a slot when the trial succeeded still rests there, released. A box knocked out of
its slot, sliding, or taken up again makes the success a false one.
"""

from __future__ import annotations

from workcell.sim.world import World
from workcell.tasks.palletize.judge import filled_slots
from workcell.tasks.palletize.layout import PalletLayout
from workcell.tasks.palletize.scene import resting


class SlotsStayFilled:
    """Watches the boxes that filled ``world``'s pallet when its trial succeeded."""

    def __init__(self, world: World) -> None:
        self._layout = PalletLayout.of(world.conditions.as_dict(), world.config)
        self._watched = filled_slots(world, self._layout)
        """Slot index to box index."""

    @property
    def objects(self) -> int:
        return len(self._watched)

    def why_undone(self, world: World, settling: bool) -> str | None:
        boxes = world.boxes
        for slot, box in sorted(self._watched.items()):
            if world.grasp.holding is boxes.slots[box]:
                return f"box {box} held again"
            if self._layout.slot_of(boxes.position(world.data, boxes.slots[box])) != slot:
                return f"box {box} out of slot {slot + 1}"
            if not settling and not resting(world, box):
                speed = boxes.speed(world.data, boxes.slots[box])
                return f"box {box} moving ({speed:.2f} m/s) in slot {slot + 1}"
        return None

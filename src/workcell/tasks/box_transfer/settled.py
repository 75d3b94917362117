"""Box transfer's settled check: each box the trial delivered stays delivered.

Data generation runs the simulation on for a second after a success
(:mod:`workcell.generate.recheck`) and asks each control period whether the boxes the
trial delivered are still at rest in the zone, released
(:meth:`~workcell.sim.target.TargetZone.rests_in`), until the scene takes them away
(:mod:`workcell.tasks.box_transfer.scene` clears a delivered box one second after its
delivery). A box that slides, is knocked or picked up again makes the success a false one.
While settling, a box in the zone and let go of may still be moving: the judge's rest is a
moment's speed, so a box let go of a centimetre above the table, slow for an instant, is
delivered then, and falls and bounces once before it rests.
"""

from __future__ import annotations

from workcell.sim.boxes import BoxSlot, BoxState
from workcell.sim.world import World


class DeliveriesStay:
    """Watches the boxes ``world``'s trial had delivered when it was made."""

    def __init__(self, world: World) -> None:
        self._watched: list[BoxSlot] = [
            slot for slot in world.boxes.slots if slot.state is BoxState.DELIVERED
        ]

    @property
    def objects(self) -> int:
        return len(self._watched)

    def why_undone(self, world: World, settling: bool) -> str | None:
        boxes, held = world.boxes, world.grasp.holding
        # a box no longer DELIVERED was taken away by the scene (and may already ride the
        # belt again, fed anew): it had stayed delivered until then
        self._watched = [slot for slot in self._watched if slot.state is BoxState.DELIVERED]
        for slot in self._watched:
            position = boxes.position(world.data, slot)
            if settling and slot is not held and world.zone.contains(position):
                continue
            if world.zone.rests_in(world.data, boxes, slot, held):
                continue
            if slot is held:
                return f"box {slot.index} held again"
            if not world.zone.contains(position):
                return f"box {slot.index} out of the zone"
            return f"box {slot.index} moving ({boxes.speed(world.data, slot):.2f} m/s) in the zone"
        return None

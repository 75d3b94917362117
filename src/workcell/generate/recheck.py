"""Settled success, checked again: an attempt counts only if its success still holds a second
later.

The task's judge ends a trial at the first frame instant its task is done (box transfer: the
box rests in the zone, released). The generator then keeps the simulation running
:data:`RECHECK_S` of sim time more, its operator still acting, and watches every control
period that each box the trial delivered stays delivered: at rest in the zone, released
(:meth:`~workcell.sim.target.DeliveryZone.delivered`), until the scene takes it away (box
transfer clears a delivered box one second after its delivery). A box that slides, is
knocked or picked up again in that second makes the success a false one. Only in the first
:data:`SETTLE_S` may a box still in the zone and let go of be moving: the judge's rest is a
moment's speed, so a box a person's operator lets go of a centimetre above the table, slow
for an instant, is delivered then, and falls and bounces once before it rests.
"""

from __future__ import annotations

from dataclasses import dataclass

from workcell.control.simulation import Simulation
from workcell.sim.boxes import BoxState
from workcell.task.operator import Operator

RECHECK_S = 1.0
"""How long after a success it is checked again (s of sim time)."""
SETTLE_S = 0.25
"""How long after a success a box in the zone, let go of, may still come to rest (s)."""


@dataclass(frozen=True)
class Recheck:
    """Whether a success held for :data:`RECHECK_S`, and if not, why."""

    held: bool
    reason: str | None = None

    def as_dict(self) -> dict[str, object]:
        return {
            "seconds": RECHECK_S,
            "settle_s": SETTLE_S,
            "held": self.held,
            "reason": self.reason,
        }


def recheck(sim: Simulation, operator: Operator) -> Recheck:
    """Run ``sim`` on for :data:`RECHECK_S` with ``operator`` acting and check each control
    period that the delivered boxes stay delivered."""
    world = sim.world
    boxes = world.boxes
    delivered = [slot for slot in boxes.slots if slot.state is BoxState.DELIVERED]
    if not delivered:
        return Recheck(False, "no delivered box to check")
    steps = max(1, round(RECHECK_S / sim.control_dt))
    for step in range(1, steps + 1):
        sim.step(operator.act(world))
        held = world.grasp.holding
        # a box no longer DELIVERED was taken away by the scene (and may already ride the
        # belt again, fed anew): it had stayed delivered until then
        delivered = [slot for slot in delivered if slot.state is BoxState.DELIVERED]
        settling = step * sim.control_dt <= SETTLE_S + 1e-9
        for slot in delivered:
            position = boxes.position(world.data, slot)
            if settling and slot is not held and world.zone.contains(position):
                continue
            if not world.zone.delivered(world.data, boxes, slot, held):
                if slot is held:
                    what = "held again"
                elif not world.zone.contains(position):
                    what = "out of the zone"
                else:
                    what = f"moving ({boxes.speed(world.data, slot):.2f} m/s) in the zone"
                return Recheck(
                    False, f"box {slot.index} {what} {step * sim.control_dt:.2f} s after success"
                )
    return Recheck(True)

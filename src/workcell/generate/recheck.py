"""Settled success, checked again: an attempt counts only if its success still holds a second
later.

The task's judge ends a trial at the first frame instant its task is done. The generator
then keeps the simulation running :data:`RECHECK_S` of sim time more, its operator still
acting, and asks the task's settled check (:meth:`workcell.tasks.Task.settled_check`; box
transfer's: :mod:`workcell.tasks.box_transfer.settled`) every control period whether the
objects the trial completed are still completed. One that slides, is knocked or picked up
again in that second makes the success a false one. Only in the first :data:`SETTLE_S`
may an object in place and let go of still be coming to rest.
"""

from __future__ import annotations

from dataclasses import dataclass

from workcell.control.simulation import Simulation
from workcell.task.operator import Operator
from workcell.tasks.task import Task

RECHECK_S = 1.0
"""How long after a success it is checked again (s of sim time)."""
SETTLE_S = 0.25
"""How long after a success an object in place, let go of, may still come to rest (s)."""


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


def recheck(sim: Simulation, operator: Operator, task: Task) -> Recheck:
    """Run ``sim`` on for :data:`RECHECK_S` with ``operator`` acting and check each control
    period that the objects ``task``'s trial completed stay completed."""
    world = sim.world
    check = task.settled_check(world)
    if check is None:
        return Recheck(False, f"the task {task.name} has no settled check")
    if check.objects == 0:
        return Recheck(False, "no completed object to check")
    steps = max(1, round(RECHECK_S / sim.control_dt))
    for step in range(1, steps + 1):
        sim.step(operator.act(world))
        settling = step * sim.control_dt <= SETTLE_S + 1e-9
        undone = check.why_undone(world, settling)
        if undone is not None:
            return Recheck(False, f"{undone} {step * sim.control_dt:.2f} s after success")
    return Recheck(True)

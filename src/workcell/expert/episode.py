"""Run the expert on one box and report how it went (box transfer judges the delivery)."""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass

from workcell.control.simulation import Simulation
from workcell.expert.operator import ExpertOperator
from workcell.tasks.box_transfer import BoxTransfer

StepObserver = Callable[[Simulation], None]


@dataclass(frozen=True)
class OneBoxResult:
    delivered: bool
    sim_time_s: float
    wall_time_s: float
    """Wall time of the simulation loop alone (observers excluded)."""

    @property
    def real_time_factor(self) -> float:
        return self.sim_time_s / self.wall_time_s if self.wall_time_s > 0 else float("inf")


def deliver_one_box(
    sim: Simulation,
    expert: ExpertOperator,
    time_limit_s: float = 120.0,
    observer: StepObserver | None = None,
) -> OneBoxResult:
    """Step ``sim`` with ``expert`` until a box is delivered or ``time_limit_s`` of sim time.

    ``observer`` is called after every control step (to render video, show progress); its
    time is not counted in the result's wall time.
    """
    judge = BoxTransfer().new_trial(1)
    delivered = False
    loop_wall = 0.0
    while sim.time < time_limit_s - 1e-9 and not delivered:
        start = time.perf_counter()
        for event in sim.step(expert.act(sim.world)):
            judge.observe(event)
        loop_wall += time.perf_counter() - start
        delivered = judge.evaluate(sim.world).success
        if observer is not None:
            observer(sim)
    return OneBoxResult(delivered=delivered, sim_time_s=sim.time, wall_time_s=loop_wall)

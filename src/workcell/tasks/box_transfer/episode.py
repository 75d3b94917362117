"""Run the expert on one box and say whether it delivered: one trial of the session runner (the
one episode loop), judged by the box-transfer task."""

from __future__ import annotations

from dataclasses import dataclass

from workcell.control.simulation import Simulation
from workcell.task.one_trial import run_one_trial
from workcell.task.operator import Operator


@dataclass(frozen=True)
class OneBoxResult:
    delivered: bool
    sim_time_s: float


def deliver_one_box(
    sim: Simulation, expert: Operator, seed: int, time_limit_s: float = 120.0
) -> OneBoxResult:
    """Reset ``sim``'s world with ``seed`` and let ``expert`` (the expert, or an operator
    wrapping it) deliver a box: a trial with no countdown, ended by the task's judge or after
    ``time_limit_s`` of sim time (:func:`workcell.task.one_trial.run_one_trial`, which also
    times the loop and takes an observer)."""
    result = run_one_trial(sim, expert, seed, time_limit_s)
    return OneBoxResult(delivered=result.succeeded, sim_time_s=result.sim_time_s)

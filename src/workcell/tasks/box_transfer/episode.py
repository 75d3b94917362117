"""Run the expert on one box and report how it went: one trial of the session runner (the
one episode loop), judged by the box-transfer task."""

from __future__ import annotations

from dataclasses import dataclass

from workcell.control.simulation import Simulation
from workcell.task.one_trial import StepObserver, run_one_trial
from workcell.tasks.elements.expert import ExpertOperator


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
    seed: int,
    time_limit_s: float = 120.0,
    observer: StepObserver | None = None,
) -> OneBoxResult:
    """Reset ``sim``'s world with ``seed`` and let ``expert`` deliver a box: a trial with
    no countdown, ended by the task's judge or after ``time_limit_s`` of sim time
    (:func:`workcell.task.one_trial.run_one_trial`).

    ``observer`` is called after every control step (to render video, show progress); its
    time is not counted in the result's wall time.
    """
    result = run_one_trial(sim, expert, seed, time_limit_s, observer=observer)
    return OneBoxResult(
        delivered=result.succeeded, sim_time_s=result.sim_time_s, wall_time_s=result.wall_time_s
    )

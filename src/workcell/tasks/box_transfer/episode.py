"""Run the expert on one box and report how it went: one trial of the session runner (the
one episode loop), judged by the box-transfer task."""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from dataclasses import dataclass

from workcell.control.simulation import Simulation
from workcell.session.config import SessionConfig, TaskConfig
from workcell.task.runner import SessionRunner
from workcell.task.schedule import TrialSpec
from workcell.tasks.elements.expert import ExpertOperator

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
    seed: int,
    time_limit_s: float = 120.0,
    observer: StepObserver | None = None,
) -> OneBoxResult:
    """Reset ``sim``'s world with ``seed`` and let ``expert`` deliver a box: a trial with
    no countdown, ended by the task's judge or after ``time_limit_s`` of sim time.

    ``observer`` is called after every control step (to render video, show progress); its
    time is not counted in the result's wall time.
    """
    task = TaskConfig(mode="practice", time_limit_s=time_limit_s, countdown_s=0.0)
    config = dataclasses.replace(SessionConfig(world=sim.config), task=task)
    runner = SessionRunner(config, sim, expert, max_trials=1)
    loop_wall = 0.0

    def stepped() -> None:
        nonlocal loop_wall
        loop_wall += runner.last_step_wall_s
        if observer is not None:
            observer(sim)

    runner.start(TrialSpec(0, "practice", None, None, 1, time_limit_s), world_seed=seed)
    (result,) = runner.run(after_step=stepped)
    return OneBoxResult(
        delivered=result.outcome == "success", sim_time_s=sim.time, wall_time_s=loop_wall
    )

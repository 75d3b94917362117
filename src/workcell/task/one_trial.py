"""One trial of any task, headless, with no countdown: one run of the session runner (the
one episode loop), judged by the session's task (``task.kind``). What ``workcell demo`` and
the experts' episode helpers run."""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from dataclasses import dataclass

from workcell.control.simulation import Simulation
from workcell.session.config import SessionConfig, TaskConfig
from workcell.task.events import Outcome
from workcell.task.operator import Operator
from workcell.task.runner import SessionRunner
from workcell.task.schedule import TrialSpec

StepObserver = Callable[[Simulation], None]


@dataclass(frozen=True)
class OneTrialResult:
    outcome: Outcome
    stage: str
    """The furthest of the task's stages the trial reached."""
    sim_time_s: float
    """Simulated time the trial ran (raised to the task's least time limit if it needs)."""
    wall_time_s: float
    """Wall time of the simulation loop alone (observers excluded)."""

    @property
    def succeeded(self) -> bool:
        return self.outcome == "success"

    @property
    def real_time_factor(self) -> float:
        return self.sim_time_s / self.wall_time_s if self.wall_time_s > 0 else float("inf")


def run_one_trial(
    sim: Simulation,
    operator: Operator,
    seed: int,
    time_limit_s: float,
    *,
    kind: str | None = None,
    observer: StepObserver | None = None,
) -> OneTrialResult:
    """Reset ``sim``'s world with ``seed`` and let ``operator`` do one trial of the task
    ``kind`` (default: the session default's) that asks one object (or the task's own
    count), ended by the task's judge or after ``time_limit_s`` of sim time.

    ``sim`` must hold the task's scene. ``observer`` is called after every control step (to
    render video, show progress); its time is not counted in the result's wall time.
    """
    task = TaskConfig(mode="practice", time_limit_s=time_limit_s, countdown_s=0.0)
    if kind is not None:
        task = dataclasses.replace(task, kind=kind)
    config = dataclasses.replace(SessionConfig(world=sim.config), task=task)
    runner = SessionRunner(config, sim, operator, max_trials=1)
    loop_wall = 0.0

    def stepped() -> None:
        nonlocal loop_wall
        loop_wall += runner.last_step_wall_s
        if observer is not None:
            observer(sim)

    runner.start(TrialSpec(0, "practice", None, None, 1, time_limit_s), world_seed=seed)
    (result,) = runner.run(after_step=stepped)
    return OneTrialResult(
        outcome=result.outcome, stage=result.stage, sim_time_s=sim.time, wall_time_s=loop_wall
    )

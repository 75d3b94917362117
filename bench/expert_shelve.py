"""Shelve's expert, measured (issue 33): its success over 100 unseen seeds in D0 and in
D2, with Wilson intervals, and how the failures went (the furthest stage each reached).

Each trial is one trial of the session runner (the one episode loop) with the task's own
judge: success once the box has rested on the asked board, released and still, for 1 s.
Target: >= 95/100 in D0 and >= 90/100 in D2.

    .venv/bin/python bench/expert_shelve.py                  # 100 seeds from 1000, D0 and D2
    .venv/bin/python bench/expert_shelve.py --trials 20 --worlds D1
    .venv/bin/python bench/expert_shelve.py --grasp physical       # contact and friction alone
"""

from __future__ import annotations

import argparse
import dataclasses
import time
from collections import Counter
from collections.abc import Sequence

from workcell.control.simulation import Simulation
from workcell.expert.skill import ExpertConfig
from workcell.metrics import wilson_interval
from workcell.session.config import SessionConfig, TaskConfig
from workcell.sim.config import GRASP_MODES, GraspMode
from workcell.task.runner import SessionRunner
from workcell.task.schedule import TrialSpec
from workcell.tasks import WORLDS
from workcell.tasks.registry import load_task
from workcell.tasks.shelve.shelf import ShelfLayout
from workcell.tasks.worlds import randomization

FIRST_SEED = 1000
"""Seeds from here: none of the tests' or the collections' seeds."""
TIME_LIMIT_S = 60.0


@dataclasses.dataclass
class WorldResult:
    world: str
    successes: int = 0
    n: int = 0
    sim_s: float = 0.0
    wall_s: float = 0.0
    by_shelf: Counter[str] = dataclasses.field(default_factory=Counter)
    asked: Counter[str] = dataclasses.field(default_factory=Counter)
    failures: list[str] = dataclasses.field(default_factory=list)

    def line(self) -> str:
        low, high = wilson_interval(self.successes, self.n)
        shelves = ", ".join(f"{k} {self.by_shelf[k]}/{self.asked[k]}" for k in sorted(self.asked))
        return (
            f"{self.world}: {self.successes}/{self.n} = {100 * self.successes / self.n:5.1f} % "
            f"[Wilson 95 % {100 * low:5.1f}, {100 * high:5.1f}]  by shelf: {shelves}; "
            f"{self.sim_s / self.n:4.1f} s sim per trial, {self.wall_s:5.0f} s wall"
        )


def run_world(world_name: str, seeds: Sequence[int], grasp: GraspMode = "assisted") -> WorldResult:
    task = load_task("shelve")
    ranges = next(r for name, r in task.worlds.items() if name == world_name)
    world = dataclasses.replace(
        SessionConfig().world, randomization=randomization(ranges), grasp=grasp
    )
    task_config = TaskConfig(
        kind=task.name, mode="practice", time_limit_s=TIME_LIMIT_S, countdown_s=0.0
    )
    config = dataclasses.replace(SessionConfig(world=world), task=task_config)
    sim = Simulation(world, task.scene())
    result = WorldResult(world_name)
    for seed in seeds:
        runner = SessionRunner(config, sim, task.expert(ExpertConfig()), max_trials=1)
        runner.start(TrialSpec(0, "practice", None, None, 1, TIME_LIMIT_S), world_seed=seed)
        started = time.perf_counter()
        (trial,) = runner.run()
        result.wall_s += time.perf_counter() - started
        result.sim_s += trial.elapsed_s
        shelf = ShelfLayout.from_recorded(sim.world.conditions.task_values).asked_name
        result.n += 1
        result.asked[shelf] += 1
        if trial.outcome == "success":
            result.successes += 1
            result.by_shelf[shelf] += 1
        else:
            stage = runner.hud().stage
            result.failures.append(f"seed {seed}: {trial.outcome} at stage {stage} ({shelf})")
    return result


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--trials", type=int, default=100)
    parser.add_argument("--first-seed", type=int, default=FIRST_SEED)
    parser.add_argument("--worlds", nargs="+", choices=WORLDS, default=["D0", "D2"])
    parser.add_argument("--grasp", choices=GRASP_MODES, default="assisted")
    args = parser.parse_args(argv)
    seeds = range(args.first_seed, args.first_seed + args.trials)
    for world_name in args.worlds:
        result = run_world(world_name, seeds, args.grasp)
        print(result.line(), flush=True)
        for failure in result.failures:
            print(f"  {failure}", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

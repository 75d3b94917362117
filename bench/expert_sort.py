"""The sort task's expert over unseen seeds, in D0 and D2 (issue 33): success with Wilson
intervals and n, and how the trials that failed ended.

Each trial is one trial of the session runner (the one episode loop), judged by the sort
task: ``--required`` boxes (default 4, two of each kind) must be sorted within
``--time-limit`` seconds of simulated time. Seeds from ``--first-seed`` (default 1000)
on: worlds no test uses. Target: >= 95/100 in D0, >= 90/100 in D2.

    .venv/bin/python bench/expert_sort.py                    # 100 trials in D0 and in D2
    .venv/bin/python bench/expert_sort.py --worlds D1 --trials 20
"""

from __future__ import annotations

import argparse
import dataclasses
import sys
import time
from collections import Counter

from workcell.control.simulation import Simulation
from workcell.expert.skill import ExpertConfig
from workcell.metrics import wilson_interval
from workcell.session.config import SessionConfig, TaskConfig
from workcell.sim.config import WorldConfig
from workcell.task.runner import SessionRunner
from workcell.task.schedule import TrialSpec
from workcell.tasks import WORLDS
from workcell.tasks.sort.judge import sort_scene
from workcell.tasks.sort.task import Sort
from workcell.tasks.worlds import randomization


def run_world(world: str, trials: int, first_seed: int, required: int, limit_s: float) -> None:
    task = Sort()
    config = WorldConfig(randomization=randomization(task.worlds[world]))  # type: ignore[index]
    sim = Simulation(config, task.scene())
    expert = task.expert(ExpertConfig())
    session = dataclasses.replace(
        SessionConfig(world=config),
        task=TaskConfig(kind=task.name, mode="practice", time_limit_s=limit_s, countdown_s=0.0),
    )
    successes, sim_s, ends = 0, 0.0, Counter[str]()
    started = time.perf_counter()
    for seed in range(first_seed, first_seed + trials):
        runner = SessionRunner(session, sim, expert, max_trials=1)
        runner.start(TrialSpec(0, "practice", None, None, required, limit_s), world_seed=seed)
        (result,) = runner.run()
        success = result.outcome == "success"
        successes += success
        sim_s += result.elapsed_s
        end = f"{result.outcome} at {result.stage}, {result.boxes_done}/{required} sorted"
        end += ", missorted" if sort_scene(sim.world).missorted else ""
        if not success:
            ends[end] += 1
        done = seed - first_seed + 1
        print(f"  {world} seed {seed}: {end} in {result.elapsed_s:.1f} s ({successes}/{done})")
    low, high = wilson_interval(successes, trials)
    wall = time.perf_counter() - started
    print(
        f"{world}: {successes}/{trials} sorted all {required} = {100 * successes / trials:.1f} % "
        f"[Wilson 95 % {100 * low:.1f}, {100 * high:.1f}]; mean trial {sim_s / trials:.1f} s "
        f"sim, {wall / trials:.1f} s wall",
        flush=True,
    )
    for end, count in ends.most_common():
        print(f"  {count} x {end}")


def main() -> None:
    sys.stdout.reconfigure(line_buffering=True)  # type: ignore[union-attr]
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--worlds", default="D0,D2", help="comma-separated: D0, D1, D2")
    parser.add_argument("--trials", type=int, default=100)
    parser.add_argument("--first-seed", type=int, default=1000)
    parser.add_argument("--required", type=int, default=4)
    parser.add_argument("--time-limit", type=float, default=150.0, help="seconds of sim time")
    args = parser.parse_args()
    worlds = args.worlds.split(",")
    unknown = [w for w in worlds if w not in WORLDS]
    if unknown:
        parser.error(f"--worlds: unknown {unknown}; the worlds are {', '.join(WORLDS)}")
    for world in worlds:
        run_world(world, args.trials, args.first_seed, args.required, args.time_limit)


if __name__ == "__main__":
    main()

"""Simulation speed: raw physics against the full control loop, on one core.

Prints, measured in one run:
- the raw ``mj_step`` rate of the full scene (robot holding still, boxes on the belt),
- the full loop rate (physics + IK + grasp logic + feeder + the expert), in physics steps/s,
- their ratio, and the real-time factor of one expert trial.

Targets (issue 2): full loop >= 25x real time and >= 0.4 of the raw rate.
Run: ``make bench`` or ``.venv/bin/python bench/sim.py [--trials N]``.
"""

from __future__ import annotations

import argparse
import os
import time

import mujoco

from workcell.control.simulation import Simulation
from workcell.expert import ExpertConfig, ExpertOperator
from workcell.sim.config import WorldConfig
from workcell.sim.events import BoxDelivered

TRIAL_LIMIT_S = 120.0


def pin_to_one_core() -> None:
    if hasattr(os, "sched_setaffinity"):
        os.sched_setaffinity(0, {min(os.sched_getaffinity(0))})


def raw_step_rate(sim: Simulation, seconds: float) -> float:
    """Physics steps per second on the scene as the expert finds it mid-task, stepped in
    one batched call (no Python overhead at all): the strictest baseline."""
    model, data = sim.world.model, sim.world.data
    steps = round(seconds / model.opt.timestep)
    start = time.perf_counter()
    mujoco.mj_step(model, data, nstep=steps)
    return float(steps / (time.perf_counter() - start))


def expert_trial(sim: Simulation, seed: int) -> tuple[bool, float, float]:
    """One expert delivery; returns (delivered, sim seconds, wall seconds)."""
    sim.reset(seed)
    expert = ExpertOperator(ExpertConfig(), seed=seed)
    delivered = False
    start = time.perf_counter()
    while sim.time < TRIAL_LIMIT_S and not delivered:
        events = sim.step(expert.act(sim.world))
        delivered = any(isinstance(e, BoxDelivered) for e in events)
    return delivered, sim.time, time.perf_counter() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--trials", type=int, default=3, help="expert trials to time")
    parser.add_argument("--grasp", choices=("assisted", "physical"), default="assisted")
    args = parser.parse_args()
    pin_to_one_core()

    sim = Simulation(WorldConfig(grasp=args.grasp))
    timestep = sim.world.model.opt.timestep
    sim_total = wall_total = 0.0
    delivered = 0
    for seed in range(args.trials):
        ok, sim_s, wall_s = expert_trial(sim, seed)
        delivered += ok
        sim_total += sim_s
        wall_total += wall_s
    loop_rate = sim_total / timestep / wall_total

    # Raw physics on the same scene: reset and let boxes arrive, then time bare mj_step.
    sim.reset(0)
    expert = ExpertOperator(ExpertConfig(), seed=0)
    while sim.time < 14.0:
        sim.step(expert.act(sim.world))
    raw_rate = raw_step_rate(sim, seconds=10.0)

    rtf = sim_total / wall_total
    print(f"scene: nq={sim.world.model.nq} nv={sim.world.model.nv} timestep={timestep} s")
    raw_rtf = raw_rate * timestep
    print(f"raw mj_step rate   : {raw_rate:8.0f} steps/s  ({raw_rtf:.1f}x real time)")
    print(f"full loop rate     : {loop_rate:8.0f} steps/s  ({rtf:.1f}x real time)")
    print(f"full loop / raw    : {loop_rate / raw_rate:8.2f}          (target >= 0.40)")
    print(f"expert trial RTF   : {rtf:8.1f}x         (target >= 25x)")
    print(f"delivered          : {delivered}/{args.trials} expert trials")


if __name__ == "__main__":
    main()

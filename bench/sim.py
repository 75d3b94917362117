"""Simulation speed: raw physics against the full control loop, on one core.

Prints, measured in one run:
- the raw ``mj_step`` rate of the full scene (robot holding still, boxes on the belt),
  timed from one saved state before the trials and after each seed's, the median of those,
- the full loop rate (physics + IK + grasp logic + feeder + the expert), in physics steps/s,
  at each IK rate of ``--ik-hz`` (0: the IK solves every control period, the default;
  trials of each rate interleaved seed by seed),
- their ratio, the real-time factor of the expert's trials, and how closely each arm
  tracks its commanded TCP target while it follows (measured TCP against the target, base
  frame; the time to compute it is not counted).

Targets (issue 2): full loop >= 25x real time and >= 0.4 of the raw rate; (issue 19) >= 35x
and >= 0.55, tracking unchanged.
Run: ``make bench`` or ``.venv/bin/python bench/sim.py [--trials N] [--ik-hz 0,20]
[--control-hz 100]``.
"""

from __future__ import annotations

import argparse
import os
import time
from dataclasses import dataclass, field

import mujoco
import numpy as np

from workcell.control.simulation import Simulation
from workcell.expert import ExpertConfig
from workcell.sim.config import RobotConfig, WorldConfig
from workcell.sim.events import BoxCompleted
from workcell.tasks.box_transfer.task import BoxTransfer
from workcell.tasks.elements.expert import ExpertOperator
from workcell.teleop.operator import measured_tcp

TRIAL_LIMIT_S = 120.0
STATE = mujoco.mjtState.mjSTATE_INTEGRATION


def pin_to_one_core() -> None:
    if hasattr(os, "sched_setaffinity"):
        os.sched_setaffinity(0, {min(os.sched_getaffinity(0))})


class RawPhysics:
    """The baseline: the bare ``mj_step`` rate on the scene as the expert finds it mid-task
    (robot holding still at the start, boxes on the belt), stepped in one batched call with
    no Python overhead at all, the strictest baseline. Measured from the same saved state
    between the trials, so that it samples the machine when the loop does; its median is
    the figure."""

    def __init__(self, config: WorldConfig) -> None:
        sim = Simulation(config, BoxTransfer().scene())
        sim.reset(0)
        expert = ExpertOperator(ExpertConfig(), seed=0)
        while sim.time < 14.0:
            sim.step(expert.act(sim.world))
        self.model, self.data = sim.world.model, sim.world.data
        self.state = np.empty(mujoco.mj_stateSize(self.model, STATE))
        mujoco.mj_getState(self.model, self.data, self.state, STATE)
        self.rates: list[float] = []

    def measure(self, seconds: float) -> None:
        """Time ``seconds`` of simulated physics from the saved state."""
        mujoco.mj_setState(self.model, self.data, self.state, STATE)
        steps = round(seconds / self.model.opt.timestep)
        start = time.perf_counter()
        mujoco.mj_step(self.model, self.data, nstep=steps)
        self.rates.append(steps / (time.perf_counter() - start))

    @property
    def rate(self) -> float:
        return float(np.median(self.rates))


@dataclass
class Run:
    """One IK rate's trials: sim and wall seconds, deliveries, tracking errors (m)."""

    sim_s: float = 0.0
    wall_s: float = 0.0
    delivered: int = 0
    errors: list[float] = field(default_factory=list)


def expert_trial(sim: Simulation, seed: int, run: Run) -> None:
    """One expert delivery, added to ``run``."""
    sim.reset(seed)
    expert = ExpertOperator(ExpertConfig(), seed=seed)
    delivered = False
    wall = 0.0
    while sim.time < TRIAL_LIMIT_S and not delivered:
        start = time.perf_counter()
        command = expert.act(sim.world)
        events = sim.step(command)
        wall += time.perf_counter() - start
        delivered = any(isinstance(e, BoxCompleted) for e in events)
        for side, arm in (("l", command.left), ("r", command.right)):
            if arm.follow:
                measured = np.array(measured_tcp(sim.world, side)[:3])
                run.errors.append(float(np.linalg.norm(measured - np.array(arm.position))))
    run.sim_s += sim.time
    run.wall_s += wall
    run.delivered += delivered


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--trials", type=int, default=3, help="expert trials to time per rate")
    parser.add_argument("--grasp", choices=("assisted", "physical"), default="assisted")
    parser.add_argument("--ik-hz", default="0,20", help="IK rates to compare (0: every period)")
    parser.add_argument(
        "--control-hz",
        type=float,
        default=RobotConfig().control_hz,
        help="control rate of every run (100: the rate a person drives at in workcell serve)",
    )
    args = parser.parse_args()
    pin_to_one_core()

    rates = [float(hz) for hz in args.ik_hz.split(",")]
    sims = {
        hz: Simulation(
            WorldConfig(grasp=args.grasp, robot=RobotConfig(control_hz=args.control_hz, ik_hz=hz)),
            BoxTransfer().scene(),
        )
        for hz in rates
    }
    runs = {hz: Run() for hz in rates}
    raw = RawPhysics(WorldConfig(grasp=args.grasp))
    raw.measure(seconds=10.0)
    for seed in range(args.trials):
        for hz in rates:
            expert_trial(sims[hz], seed, runs[hz])
        raw.measure(seconds=10.0)
    raw_rate = raw.rate
    sim = sims[rates[0]]
    timestep = sim.world.model.opt.timestep
    control_hz = sim.world.config.robot.control_hz

    print(f"scene: nq={sim.world.model.nq} nv={sim.world.model.nv} timestep={timestep} s")
    spread = f"{min(raw.rates):.0f}-{max(raw.rates):.0f}"
    print(
        f"raw mj_step rate   : {raw_rate:8.0f} steps/s  ({raw_rate * timestep:.1f}x real time; "
        f"median of {len(raw.rates)}, {spread})"
    )
    for hz in rates:
        run = runs[hz]
        loop_rate = run.sim_s / timestep / run.wall_s
        errors = np.array(run.errors) * 1000
        label = f"IK {hz or control_hz:g} Hz" + (" (every period)" if hz in (0, control_hz) else "")
        print(f"\n{label}, control {control_hz:g} Hz")
        rtf = run.sim_s / run.wall_s
        ratio = loop_rate / raw_rate
        print(f"  full loop rate   : {loop_rate:8.0f} steps/s  ({rtf:.1f}x real time)")
        print(f"  full loop / raw  : {ratio:8.2f}          (target >= 0.40; issue 19: >= 0.55)")
        print(f"  delivered        : {run.delivered}/{args.trials} expert trials")
        p95 = np.percentile(errors, 95)
        print(
            f"  tracking error   : mean {errors.mean():.1f} mm, p95 {p95:.1f} mm "
            "(measured TCP against its target while following)"
        )


if __name__ == "__main__":
    main()

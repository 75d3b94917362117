"""How closely a hand follows its target at the teleop IK rates (issue 38, item 3).

Issue 38 lets ``world.robot.teleop_ik_hz`` drop by default only where the input-to-State
latency and the tracking error, measured in the same run, stay within today's figures.
The IK rate does not change when a State goes out (one follows every control period that
applied an input, `src/workcell/server/live.py`); this bench measures the other half.

A person's session steps at ``teleop_control_hz`` (100 Hz). Its left arm follows a target
that moves along a circle of radius ``--radius`` in the base's y-z plane, starting where
the hand is (the clutch engaged, as a person sweeping a hand); the base stands, or drives
forward while turning. Each control period, the tracking error is the distance from the
TCP the simulation shows to the target commanded that period (both in the base frame):
mean, 95th percentile and largest, after the first second. Per IK rate also the CPU
time per control period (this process, the same run) and the IK solves made.

Run: ``.venv/bin/python bench/tracking.py [--ik-hz 0,50] [--seconds 6]`` (0: the IK solves
every control period, today's default).
"""

from __future__ import annotations

import argparse
import math
import time
from dataclasses import dataclass

import numpy as np

from workcell.control.command import ArmCommand, BaseTwist, Command
from workcell.control.simulation import Simulation
from workcell.sim.config import RobotConfig, WorldConfig
from workcell.tasks.box_transfer.task import BoxTransfer

WARM_UP_S = 1.0
"""Left out of the error: the arm starts at rest while its target already moves."""


@dataclass(frozen=True)
class Motion:
    name: str
    circle_hz: float
    base: BaseTwist


MOTIONS = (
    Motion("hand 0.5 Hz, base still", 0.5, BaseTwist()),
    Motion("hand 1 Hz, base still", 1.0, BaseTwist()),
    Motion("hand 0.5 Hz, base driving", 0.5, BaseTwist(vx=0.2, vy=0.0, wz=0.3)),
)


@dataclass(frozen=True)
class Tracking:
    mean_mm: float
    p95_mm: float
    max_mm: float
    cpu_ms: float
    """CPU time per control period."""
    solves: int


def track(
    motion: Motion, control_hz: float, ik_hz: float, seconds: float, radius: float
) -> Tracking:
    robot = RobotConfig(control_hz=control_hz, ik_hz=ik_hz)
    sim = Simulation(WorldConfig(robot=robot), BoxTransfer().scene())
    sim.controller.solve_held_arms = False  # as in a person's session (TeleopDriver)
    sim.reset(0)
    for _ in range(int(control_hz)):  # a second for the arms to settle on their actuators
        sim.step(Command())
    start = sim.controller.ik.tcp_pose("l")
    centre = start.translation() - np.array([0.0, radius, 0.0])
    w, x, y, z = (float(v) for v in start.rotation().wxyz)
    errors = []
    solves = sim.controller.ik.solves
    cpu = time.process_time()
    periods = int(seconds * control_hz)
    for i in range(periods):
        phase = 2.0 * math.pi * motion.circle_hz * (i + 1) / control_hz
        target = centre + radius * np.array([0.0, math.cos(phase), math.sin(phase)])
        arm = ArmCommand(
            position=(float(target[0]), float(target[1]), float(target[2])),
            quaternion=(w, x, y, z),
            follow=True,
        )
        sim.step(Command(base=motion.base, left=arm))
        if i >= WARM_UP_S * control_hz:
            here = sim.world.to_base_frame(sim.world.tcp_pose("l")[0])
            errors.append(float(np.linalg.norm(here - target)))
    cpu = time.process_time() - cpu
    error_mm = 1000.0 * np.asarray(errors)
    return Tracking(
        mean_mm=float(error_mm.mean()),
        p95_mm=float(np.percentile(error_mm, 95)),
        max_mm=float(error_mm.max()),
        cpu_ms=1000.0 * cpu / periods,
        solves=sim.controller.ik.solves - solves,
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--ik-hz",
        default="0,50",
        help="teleop IK rates (0: every control period, the default); the first is the baseline",
    )
    parser.add_argument("--control-hz", type=float, default=RobotConfig().teleop_control_hz)
    parser.add_argument("--seconds", type=float, default=6.0, help="per motion and rate")
    parser.add_argument("--radius", type=float, default=0.08, help="the circle's radius, m")
    args = parser.parse_args()
    rates = [float(v) for v in args.ik_hz.split(",")]
    print(
        f"control {args.control_hz:g} Hz; circle radius {1000 * args.radius:g} mm; "
        f"{args.seconds:g} s per motion and rate, the first {WARM_UP_S:g} s left out"
    )
    print(
        f"{'motion':28s} {'IK Hz':>6s}  {'error mean / p95 / max (mm)':>28s}  "
        f"{'ratio of mean':>13s}  {'CPU per period':>14s}  {'ratio':>5s}  solves"
    )
    for motion in MOTIONS:
        base: Tracking | None = None
        for rate in rates:
            t = track(motion, args.control_hz, rate, args.seconds, args.radius)
            base = base or t
            print(
                f"{motion.name:28s} {rate:6g}  {t.mean_mm:8.2f} / {t.p95_mm:6.2f} / {t.max_mm:6.2f}"
                f"      {t.mean_mm / base.mean_mm:5.2f}x       {t.cpu_ms:8.3f} ms   "
                f"{t.cpu_ms / base.cpu_ms:4.2f}x  {t.solves}"
            )


if __name__ == "__main__":
    main()

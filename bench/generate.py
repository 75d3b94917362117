"""Data generation speed: expert trials per minute, with and without cameras, 1 and 2 workers.

Prints, measured in one run on this machine:
- expert trials per minute on one worker (one core), without cameras and with the three
  robot cameras at 128x128;
- trials per minute with 2 workers and the scaling from 1 to 2 workers (ratio; 2.0 ideal);
- the camera rendering cost per frame against the cost of simulating that frame (ratio).

Each run is a real ``workcell collect`` (recording into a store), so process start-up and
merging are included. Run: ``.venv/bin/python bench/generate.py [--trials N]``.

``--part scaling --repeats R`` measures only the scaling from 1 to 2 workers, as R paired
runs (1 worker then 2 workers, the order alternating between pairs so that a drift in the
machine's load does not favour one side), and prints each pair's ratio with their mean and
its 95 % interval (Student's t over the pairs): issue 19's "2 workers >= 1.8x one, stable
across runs". Each of the 2 workers simulates and writes its shard in one process (one
core); ``--one-writer inline`` (the default) makes the single worker the same, so the pairs
compare one core against two. ``--one-writer process`` gives the single worker
``collect``'s default writer process on the other core (about 1.3 cores in use), against
which 2 workers can gain at most about 2 / 1.3 = 1.5x on a 2-core machine. Each pair
also measures the machine's own scaling in the same run: raw ``mj_step`` of the world in
one process, then in two at once (a host whose second core is shared gives less than 2x
to any two processes).
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

CAMERAS = "head_cam,wrist_l_cam,wrist_r_cam"
T_975 = {1: 12.71, 2: 4.30, 3: 3.18, 4: 2.78, 5: 2.57, 6: 2.45, 7: 2.36, 8: 2.31, 9: 2.26}
"""Student's t, two-sided 95 %, by degrees of freedom (1.96 beyond)."""


def collect(folder: Path, name: str, trials: int, *extra: str) -> float:
    """Wall seconds of one collect run."""
    command = [sys.executable, "-m", "workcell", "collect", "--mode", "collection", "--json"]
    command += ["--trials", str(trials), "--store", str(folder / f"{name}.sqlite"), *extra]
    start = time.perf_counter()
    subprocess.run(command, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return time.perf_counter() - start


def per_minute(trials: int, seconds: float) -> float:
    return 60.0 * trials / seconds


PHYSICS_STEPS = 20_000
_PHYSICS = f"""
import mujoco
from workcell.session.config import SessionConfig
from workcell.sim.world import World
world = World(SessionConfig().world)
for _ in range({PHYSICS_STEPS}):
    mujoco.mj_step(world.model, world.data)
"""


def machine_scaling() -> float:
    """What the machine gives 2 processes against 1: raw ``mj_step`` of the world in one
    process, then in two at once (2 x the one's time over the pair's); 2.0 ideal."""
    command = [sys.executable, "-c", _PHYSICS]
    start = time.perf_counter()
    subprocess.run(command, check=True)
    one = time.perf_counter() - start
    start = time.perf_counter()
    pair = [subprocess.Popen(command) for _ in range(2)]
    for process in pair:
        if process.wait() != 0:
            raise SystemExit("the raw mj_step baseline failed")
    return 2 * one / (time.perf_counter() - start)


def scaling(trials: int, repeats: int, one_writer: str = "inline") -> None:
    """Paired runs of 1 and 2 workers; each pair's ratio, their mean and 95 % interval."""
    print(f"1 worker: --writer {one_writer}; 2 workers: each writes its shard inline")
    print(f"machine: raw mj_step, {PHYSICS_STEPS} steps in 1 process, then in 2 at once")
    ratios, machine = [], []
    with tempfile.TemporaryDirectory() as name:
        folder = Path(name)
        for k in range(repeats):
            order = ("one", "two") if k % 2 == 0 else ("two", "one")
            seconds = {}
            for side in order:
                workers = 1 if side == "one" else 2
                extra = ("--workers", "2") if workers == 2 else ("--writer", one_writer)
                seconds[side] = collect(folder, f"{side}-{k}", workers * trials, *extra)
            one = per_minute(trials, seconds["one"])
            two = per_minute(2 * trials, seconds["two"])
            ratios.append(two / one)
            machine.append(machine_scaling())
            print(
                f"pair {k + 1}: 1 worker {one:6.1f}, 2 workers {two:6.1f} trials/min: "
                f"{two / one:.2f}x (the machine, raw mj_step: {machine[-1]:.2f}x)"
            )
    mean = statistics.fmean(ratios)
    print(
        f"the machine's own 1 -> 2 (raw mj_step): {statistics.fmean(machine):.2f}x; "
        f"collect reaches {mean / statistics.fmean(machine):.0%} of it"
    )
    if len(ratios) > 1:
        half = T_975.get(len(ratios) - 1, 1.96) * statistics.stdev(ratios) / len(ratios) ** 0.5
        print(
            f"scaling 1 -> 2: {mean:.2f}x, 95 % interval [{mean - half:.2f}, {mean + half:.2f}] "
            f"over {len(ratios)} paired runs (target >= 1.80)"
        )
    else:
        print(f"scaling 1 -> 2: {mean:.2f}x (one pair: no interval)")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--trials", type=int, default=6, help="trials per worker")
    parser.add_argument("--part", choices=("all", "scaling"), default="all")
    parser.add_argument("--repeats", type=int, default=5, help="paired runs (--part scaling)")
    parser.add_argument(
        "--one-writer",
        choices=("inline", "process"),
        default="inline",
        help="the single worker's store writer (--part scaling; see the docstring)",
    )
    args = parser.parse_args()
    n = args.trials
    if args.part == "scaling":
        scaling(n, args.repeats, args.one_writer)
        return
    with tempfile.TemporaryDirectory() as name:
        folder = Path(name)
        plain = collect(folder, "plain", n)
        cameras = collect(folder, "cams", n, "--cameras", CAMERAS, "--camera-size", "128x128")
        two = collect(folder, "two", 2 * n, "--workers", "2")
    one_rate, two_rate = per_minute(n, plain), per_minute(2 * n, two)
    frames = n * 21.5 * 20  # about 21.5 s of trial time per expert trial at 20 Hz
    camera_cost = (cameras - plain) / frames
    sim_cost = plain / frames
    print(f"1 worker, no cameras : {one_rate:7.1f} trials/min")
    print(f"1 worker, 3 cameras  : {per_minute(n, cameras):7.1f} trials/min (128x128 each)")
    print(f"2 workers, no cameras: {two_rate:7.1f} trials/min")
    print(f"scaling 1 -> 2       : {two_rate / one_rate:7.2f}x (2.00 ideal on 2 cores)")
    print(f"cameras per frame    : {camera_cost * 1e3:7.2f} ms for 3 cameras")
    print(f"sim per frame        : {sim_cost * 1e3:7.2f} ms (everything else, incl. recording)")
    print(f"cameras / sim        : {camera_cost / sim_cost:7.2f}")


if __name__ == "__main__":
    main()

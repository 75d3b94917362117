"""Data generation speed: expert trials per minute, with and without cameras, 1 and 2 workers.

Prints, measured in one run on this machine:
- expert trials per minute on one worker (one core), without cameras and with the three
  robot cameras at 128x128;
- trials per minute with 2 workers and the scaling from 1 to 2 workers (ratio; 2.0 ideal);
- the camera rendering cost per frame against the cost of simulating that frame (ratio).

Each run is a real ``workcell collect`` (recording into a store), so process start-up and
merging are included. Run: ``.venv/bin/python bench/generate.py [--trials N]``.
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import tempfile
import time
from pathlib import Path

CAMERAS = "head_cam,wrist_l_cam,wrist_r_cam"


def collect(folder: Path, name: str, trials: int, *extra: str) -> float:
    """Wall seconds of one collect run."""
    command = [sys.executable, "-m", "workcell", "collect", "--mode", "collection", "--json"]
    command += ["--trials", str(trials), "--store", str(folder / f"{name}.sqlite"), *extra]
    start = time.perf_counter()
    subprocess.run(command, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return time.perf_counter() - start


def per_minute(trials: int, seconds: float) -> float:
    return 60.0 * trials / seconds


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--trials", type=int, default=6, help="trials per worker")
    args = parser.parse_args()
    n = args.trials
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

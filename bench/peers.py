"""Camera collection against robosuite, in one run (issue 19, item 1).

Prints the real-time factor (simulated seconds per wall second) of:
- ``workcell collect`` of expert trials recorded with no cameras and with the three robot
  cameras at 128x128 (recording, rendering and H.264 included, process start-up too);
- robosuite's TwoArmLift (two Pandas, 20 Hz control, random actions) with no cameras, and
  with three 128x128 camera observations, shadows on (robosuite's default) and off,
  stepped in a loop (rendering included, no recording, no start-up);
and the ratios of ours to robosuite's. Rounds alternate between the variants; medians are
reported.

robosuite 1.5 needs mujoco < 3.4, so it runs in a virtualenv of its own, given with
``--robosuite-python`` (``python3.11 -m venv /tmp/rs && /tmp/rs/bin/pip install
robosuite==1.5.2 "mujoco<3.4"``).

Run: ``.venv/bin/python -m bench.peers --robosuite-python /tmp/rs/bin/python [--rounds 3]``.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import tempfile
from pathlib import Path

from bench.cameras import collect_rtf

CAMERAS = 3
SIZE = 128

ROBOSUITE = r"""
import json, sys, time
import numpy as np
import robosuite as suite

cameras, shadows, steps = sys.argv[1] == "cameras", sys.argv[2] == "on", int(sys.argv[3])
names = ["frontview", "robot0_eye_in_hand", "robot1_eye_in_hand"]
env = suite.make(
    "TwoArmLift",
    robots=["Panda", "Panda"],
    has_renderer=False,
    has_offscreen_renderer=cameras,
    use_camera_obs=cameras,
    camera_names=names,
    camera_heights=128,
    camera_widths=128,
    control_freq=20,
    horizon=10**6,
)
env.reset()
if not shadows:
    env.sim.model.light_castshadow[:] = 0
rng = np.random.default_rng(0)
low, high = env.action_spec
for _ in range(10):
    env.step(rng.uniform(low, high))
start = time.perf_counter()
for _ in range(steps):
    observation, *_ = env.step(rng.uniform(low, high))
wall = time.perf_counter() - start
if cameras:
    assert all(observation[f"{n}_image"].shape == (128, 128, 3) for n in names)
print(json.dumps({"rtf": steps / env.control_freq / wall}))
"""

VARIANTS = ("ours, none", "ours, 3 cameras", "robosuite, none", "robosuite, shadows on",
            "robosuite, shadows off")  # fmt: skip


def robosuite_rtf(python: str, script: Path, cameras: bool, shadows: bool, steps: int) -> float:
    """robosuite's real-time factor in a process of its own (MUJOCO_GL=egl)."""
    environment = {**os.environ, "MUJOCO_GL": "egl", "PYOPENGL_PLATFORM": "egl"}
    done = subprocess.run(
        [python, str(script), "cameras" if cameras else "none", "on" if shadows else "off",
         str(steps)],
        capture_output=True, text=True, env=environment, check=False,
    )  # fmt: skip
    if done.returncode != 0:
        raise SystemExit(f"robosuite failed:\n{done.stderr[-2000:]}")
    rtf: float = json.loads(done.stdout.strip().splitlines()[-1])["rtf"]
    return rtf


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--robosuite-python", required=True, help="python of robosuite's venv")
    parser.add_argument("--rounds", type=int, default=3, help="rounds of the five variants")
    parser.add_argument("--trials", type=int, default=2, help="expert trials per collect run")
    parser.add_argument("--steps", type=int, default=200, help="robosuite steps per run")
    args = parser.parse_args()
    rtf: dict[str, list[float]] = {v: [] for v in VARIANTS}
    with tempfile.TemporaryDirectory() as name:
        folder = Path(name)
        script = folder / "robosuite_rtf.py"
        script.write_text(ROBOSUITE)
        for k in range(args.rounds):
            rtf["ours, none"].append(collect_rtf(folder, f"none-{k}", args.trials, None))
            rtf["ours, 3 cameras"].append(collect_rtf(folder, f"fast-{k}", args.trials, "fast"))
            python = args.robosuite_python
            rtf["robosuite, none"].append(robosuite_rtf(python, script, False, False, args.steps))
            for shadows in (True, False):
                variant = f"robosuite, shadows {'on' if shadows else 'off'}"
                rtf[variant].append(robosuite_rtf(python, script, True, shadows, args.steps))
            print(f"  round {k + 1}/{args.rounds} done", flush=True)
    median = {v: statistics.median(values) for v, values in rtf.items()}
    for variant in VARIANTS:
        runs = ", ".join(f"{v:.2f}" for v in rtf[variant])
        print(f"{variant:24s}: {median[variant]:6.2f}x real time  ({runs})")
    ours = median["ours, 3 cameras"]
    for peer in ("robosuite, shadows on", "robosuite, shadows off"):
        print(f"ours / {peer:17s}: {ours / median[peer]:6.2f}x  (three {SIZE}x{SIZE} cameras)")
    print(f"ours / robosuite, none  : {median['ours, none'] / median['robosuite, none']:6.2f}x")


if __name__ == "__main__":
    main()

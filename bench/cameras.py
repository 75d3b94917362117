"""Camera collection speed: real-time factor with the three robot cameras at each quality.

Prints, measured in one run on this machine (ratios against the run without cameras and
against ``fine``, the quality the model asks for):
- the real-time factor (simulated seconds per wall second) of an expert collection
  recorded with no cameras, with the three robot cameras at 128x128 in ``fine`` quality
  and in ``fast`` quality, each a real ``workcell collect`` (recording, rendering, H.264);
- the render cost of one three-camera frame in each quality (rendering alone), and at
  ``fast`` with every geom drawn (``cull=False``) against leaving out the geoms out of
  each camera's view (the default), with whether the pictures are the same;
- how far ``fast`` pictures are from ``fine`` ones (mean absolute difference, 0-255);
- the three cameras drawn into one framebuffer side by side (three viewports, one
  read-back) against three separate draws and read-backs, at ``fast`` quality: issue 19's
  "batch the three cameras' renders", and whether its pictures are the same.

Runs alternate between the variants (``--rounds`` rounds) and the medians are reported.
``--picture PATH`` writes the three cameras in both qualities side by side (PNG).
``--rounds 0`` times the rendering alone (no collect runs).
Run: ``.venv/bin/python bench/cameras.py [--rounds 3] [--trials 2] [--picture PATH]``.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

os.environ.setdefault("MUJOCO_GL", "egl")

import numpy as np

CAMERAS = ("head_cam", "wrist_l_cam", "wrist_r_cam")
SIZE = 128
VARIANTS = ("none", "fine", "fast")


def collect_rtf(folder: Path, name: str, trials: int, quality: str | None) -> float:
    """Simulated seconds per wall second of one ``workcell collect`` run."""
    store = folder / f"{name}.sqlite"
    command = [sys.executable, "-m", "workcell", "collect", "--mode", "collection", "--json"]
    command += ["--trials", str(trials), "--store", str(store), "--seed", "3"]
    if quality is not None:
        command += ["--cameras", ",".join(CAMERAS), "--camera-size", f"{SIZE}x{SIZE}"]
        command += ["--camera-quality", quality]
    start = time.perf_counter()
    out = subprocess.run(command, check=True, capture_output=True, text=True).stdout
    wall = time.perf_counter() - start
    rows = [json.loads(line) for line in out.splitlines() if line.startswith("{")]
    simulated = sum(float(r["elapsed_s"]) for r in rows if "elapsed_s" in r)
    return simulated / wall


def one_buffer(model: Any, data: Any, frames: int) -> tuple[float, list[np.ndarray]]:
    """Seconds per three-camera frame drawn at ``fast`` quality into one framebuffer
    (``OffscreenRenderer.render_all``: three viewports side by side, one read-back), and
    the three pictures."""
    from workcell.render import OffscreenRenderer  # noqa: PLC0415

    with OffscreenRenderer(model, SIZE, SIZE, quality="fast") as renderer:
        pictures = renderer.render_all(data, CAMERAS)
        start = time.perf_counter()
        for _ in range(frames):
            renderer.render_all(data, CAMERAS)
        cost = (time.perf_counter() - start) / frames
    return cost, [pictures[camera] for camera in CAMERAS]


def render_costs(frames: int) -> tuple[dict[str, float], float, dict[str, list[np.ndarray]]]:
    """Seconds per three-camera frame in each quality (and ``one buffer``: fast, drawn
    into one framebuffer), the mean absolute difference of the fast pictures from the
    fine ones, and the pictures."""
    from workcell.control.command import Command  # noqa: PLC0415
    from workcell.control.simulation import Simulation  # noqa: PLC0415
    from workcell.render import OffscreenRenderer  # noqa: PLC0415
    from workcell.sim.config import WorldConfig  # noqa: PLC0415

    sim = Simulation(WorldConfig())
    sim.reset(3)
    for _ in range(round(4.0 / sim.control_dt)):  # a box on the belt
        sim.step(Command())
    costs, pictures = {}, {}
    for variant, quality, cull in (
        ("fine", "fine", True),
        ("fast", "fast", True),
        ("every geom", "fast", False),  # fast, without leaving out geoms out of view
    ):
        model = sim.world.model
        with OffscreenRenderer(model, SIZE, SIZE, quality=quality, cull=cull) as renderer:  # type: ignore[arg-type]
            pictures[variant] = [renderer.render(sim.world.data, c).copy() for c in CAMERAS]
            start = time.perf_counter()
            for _ in range(frames):
                for camera in CAMERAS:
                    renderer.render(sim.world.data, camera)
            costs[variant] = (time.perf_counter() - start) / frames
    costs["one buffer"], pictures["one buffer"] = one_buffer(
        sim.world.model, sim.world.data, frames
    )
    difference = float(
        np.mean(
            [
                np.abs(a.astype(float) - b.astype(float)).mean()
                for a, b in zip(pictures["fine"], pictures["fast"], strict=True)
            ]
        )
    )
    return costs, difference, pictures


def save_picture(path: Path, pictures: dict[str, list[np.ndarray]]) -> None:
    from PIL import Image  # noqa: PLC0415

    rows = [np.concatenate(pictures[q], axis=1) for q in ("fine", "fast")]
    grid = np.concatenate(rows, axis=0)
    Image.fromarray(grid).resize(
        (grid.shape[1] * 2, grid.shape[0] * 2), Image.Resampling.NEAREST
    ).save(path)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=3, help="rounds of the three variants")
    parser.add_argument("--trials", type=int, default=2, help="expert trials per collect run")
    parser.add_argument("--frames", type=int, default=100, help="frames timed per quality")
    parser.add_argument("--picture", type=Path, help="write both qualities side by side (PNG)")
    args = parser.parse_args()
    rtf: dict[str, list[float]] = {v: [] for v in VARIANTS}
    with tempfile.TemporaryDirectory() as name:
        folder = Path(name)
        for k in range(args.rounds):
            for variant in VARIANTS:
                quality = None if variant == "none" else variant
                rtf[variant].append(collect_rtf(folder, f"{variant}-{k}", args.trials, quality))
            print(f"  round {k + 1}/{args.rounds} done", flush=True)
    costs, difference, pictures = render_costs(args.frames)
    lines = []
    if args.rounds > 0:
        median = {v: statistics.median(values) for v, values in rtf.items()}
        none = median["none"]
        lines.append(("collect, no cameras", f"{none:6.2f}x real time"))
        for quality in ("fine", "fast"):
            share = median[quality] / none
            lines.append(
                (
                    f"collect, 3 cameras {SIZE}x{SIZE}, {quality}",
                    f"{median[quality]:6.2f}x real time ({share:.3f} of no cameras)",
                )
            )
        lines.append(("fast / fine (collect)", f"{median['fast'] / median['fine']:6.2f}x"))
    for variant in ("fine", "fast", "every geom", "one buffer"):
        lines.append((f"render, 3 cameras, {variant}", f"{costs[variant] * 1e3:6.2f} ms per frame"))
    lines.append(("fine / fast (render)", f"{costs['fine'] / costs['fast']:6.2f}x"))

    def same(variant: str) -> bool:
        return all(
            np.array_equal(a, b) for a, b in zip(pictures["fast"], pictures[variant], strict=True)
        )

    lines.append(
        (
            "every geom / culled (render)",
            f"{costs['every geom'] / costs['fast']:6.2f}x; pictures "
            + ("identical" if same("every geom") else "differ"),
        )
    )
    lines.append(
        (
            "fast / one buffer (render)",
            f"{costs['fast'] / costs['one buffer']:6.2f}x; pictures "
            + ("identical" if same("one buffer") else "differ"),
        )
    )
    lines.append(("fast vs fine pictures", f"{difference:6.2f} mean absolute difference (0-255)"))
    for label, value in lines:
        print(f"{label:34s}: {value}")
    if args.picture is not None:
        save_picture(args.picture, pictures)
        print(f"wrote {args.picture}")


if __name__ == "__main__":
    main()

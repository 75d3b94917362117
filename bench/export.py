"""Dataset export with camera images: the trials' recorded videos reused, or re-rendered.

``workcell collect --cameras`` records each trial's camera videos; an export with those
cameras at that size reuses them (LeRobot copies them into its videos without re-encoding,
HDF5 decodes them) instead of rendering every camera frame from the recorded states. The
baseline is the same export with ``--rerender`` (what every export did before).

The store: real expert trials recorded with the three robot cameras at 128x128 (the
recording's default). Each export runs ``--repeats`` times per variant, alternating, in
this process; printed: the median seconds, frames per second and the ratio to rendering.

Run: ``.venv/bin/python bench/export.py [--trials 2] [--repeats 3]``.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import os
import statistics
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

# MuJoCo picks its OpenGL backend when first imported (by the workcell modules below).
os.environ.setdefault("MUJOCO_GL", "egl")

from workcell.cli.main import main as workcell
from workcell.export.hdf5_export import export_hdf5
from workcell.export.lerobot_export import export_lerobot
from workcell.export.loading import ExportSummary
from workcell.export.options import ExportOptions

CAMERAS = ("head_cam", "wrist_l_cam", "wrist_r_cam")
SIZE = "128x128"
Export = Callable[[Path, Path, ExportOptions], ExportSummary]
FORMATS: dict[str, Export] = {"lerobot": export_lerobot, "hdf5": export_hdf5}


def record(folder: Path, trials: int, seed: int) -> Path:
    store = folder / "cameras.sqlite"
    argv = ["collect", "--mode", "collection", "--trials", str(trials), "--seed", str(seed)]
    argv += ["--cameras", ",".join(CAMERAS), "--camera-size", SIZE, "--json"]
    started = time.perf_counter()
    with contextlib.redirect_stdout(io.StringIO()):  # one JSON line per trial
        code = workcell([*argv, "--store", str(store)])
    if code != 0:
        sys.exit("collect failed")
    print(
        f"recorded {trials} trials with {len(CAMERAS)} cameras at {SIZE} in "
        f"{time.perf_counter() - started:.1f} s",
        file=sys.stderr,
    )
    return store


def run() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0] if __doc__ else None)
    parser.add_argument("--trials", type=int, default=2, help="expert trials in the store")
    parser.add_argument("--repeats", type=int, default=3, help="exports per variant")
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as name:
        folder = Path(name)
        store = record(folder, args.trials, args.seed)
        variants = {"reused": False, "rendered": True}
        seconds: dict[tuple[str, str], list[float]] = {}
        frames = 0
        for repeat in range(args.repeats):
            for format_name, export in FORMATS.items():
                for variant, rerender in variants.items():
                    out = folder / f"{format_name}-{variant}-{repeat}"
                    options = ExportOptions(cameras=CAMERAS, rerender=rerender)
                    summary = export(store, out, options)
                    streams = args.trials * len(CAMERAS)
                    wanted = (streams, 0) if rerender else (0, streams)
                    if (summary.rendered_videos, summary.recorded_videos) != wanted:
                        sys.exit(f"{format_name} {variant}: not what was asked ({summary})")
                    seconds.setdefault((format_name, variant), []).append(summary.seconds)
                    frames = summary.frames
    print(
        f"store: {args.trials} expert trials, {frames} frames, cameras {', '.join(CAMERAS)} "
        f"at {SIZE}; median of {args.repeats} exports"
    )
    for format_name in FORMATS:
        rendered = statistics.median(seconds[(format_name, "rendered")])
        for variant in variants:
            median = statistics.median(seconds[(format_name, variant)])
            print(
                f"{format_name:>8} {variant:>9}: {median:7.2f} s {frames / median:8.0f} "
                f"frames/s   ratio to rendering {median / rendered:6.3f} "
                f"({rendered / median:5.1f}x faster)"
            )


if __name__ == "__main__":
    run()

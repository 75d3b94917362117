"""``workcell snapshot``: run the workcell idle for a while and save one rendered picture."""

from __future__ import annotations

import argparse
import math
from pathlib import Path
from typing import TYPE_CHECKING

from workcell.errors import ConfigError

if TYPE_CHECKING:
    from workcell.cli.command import Subparsers

OVERVIEW = "overview"
CAMERAS = (OVERVIEW, "head_cam", "wrist_l_cam", "wrist_r_cam")
"""The free overview camera, then the robot's cameras as named in the model."""
MIN_SIZE, MAX_SIZE = 64, 3840
MAX_SETTLE_S = 600.0


def register(subparsers: Subparsers) -> None:
    parser = subparsers.add_parser(
        "snapshot",
        help="save a rendered picture of the workcell",
        description=(
            "Build the default workcell, let it run with the robot idle for --settle seconds "
            "of simulated time (boxes arrive on the belt), and save one picture as PNG."
        ),
    )
    parser.add_argument("--out", required=True, type=Path, help="PNG file to write")
    parser.add_argument("--width", type=int, default=1280, help="pixels (default: 1280)")
    parser.add_argument("--height", type=int, default=720, help="pixels (default: 720)")
    parser.add_argument(
        "--camera", choices=CAMERAS, default=OVERVIEW, help="viewpoint (default: overview)"
    )
    parser.add_argument(
        "--seed",
        type=int,
        default=0,
        help="seed of the world: where and how boxes land on the belt (default: 0)",
    )
    parser.add_argument(
        "--settle",
        type=float,
        default=12.0,
        metavar="S",
        help="seconds of simulated time before the picture (default: 12)",
    )
    parser.set_defaults(func=run)


def _check(args: argparse.Namespace) -> None:
    problems = []
    if Path(args.out).suffix.lower() != ".png":
        problems.append(f"--out = {str(args.out)!r}: must be a file name ending in .png")
    for name in ("width", "height"):
        value = getattr(args, name)
        if not MIN_SIZE <= value <= MAX_SIZE:
            problems.append(f"--{name} = {value}: must be {MIN_SIZE} to {MAX_SIZE} pixels")
    if not (math.isfinite(args.settle) and 0.0 <= args.settle <= MAX_SETTLE_S):
        problems.append(f"--settle = {args.settle:g}: must be 0 to {MAX_SETTLE_S:g} seconds")
    if problems:
        raise ConfigError(problems)


def run(args: argparse.Namespace) -> int:
    _check(args)
    # MuJoCo is imported here, after main() has chosen the OpenGL backend.
    from workcell.control.command import Command  # noqa: PLC0415
    from workcell.control.simulation import Simulation  # noqa: PLC0415
    from workcell.render import OffscreenRenderer, overview_camera, save_png  # noqa: PLC0415
    from workcell.sim.config import WorldConfig  # noqa: PLC0415

    sim = Simulation(WorldConfig())
    sim.reset(args.seed)
    idle = Command()
    for _ in range(round(args.settle / sim.control_dt)):
        sim.step(idle)
    model, data = sim.world.model, sim.world.data
    with OffscreenRenderer(model, args.width, args.height, shadows=True) as renderer:
        camera = overview_camera(model) if args.camera == OVERVIEW else args.camera
        image = renderer.render(data, camera)
    print(save_png(image, args.out))
    return 0

"""``workcell demo``: the autonomous expert delivers one box, headless, optionally on video."""

from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path
from typing import TYPE_CHECKING

from workcell.errors import ConfigError
from workcell.session.config import TaskConfig
from workcell.settings import check_as, declared_default
from workcell.sim.config import GRASP_MODES, WorldConfig

if TYPE_CHECKING:
    from workcell.cli.command import Subparsers
    from workcell.control.simulation import Simulation

VIDEO_FPS = 30
TIME_LIMIT_S: float = declared_default(TaskConfig, "time_limit_s")
GRASP: str = declared_default(WorldConfig, "grasp")


def register(subparsers: Subparsers) -> None:
    parser = subparsers.add_parser(
        "demo",
        help="watch the autonomous expert deliver one box",
        description=(
            "Run the scripted expert on one box in the default workcell, headless, and print "
            "whether the box was delivered, the simulated time it took and the real-time "
            "factor of the simulation loop."
        ),
    )
    parser.add_argument("--seed", type=int, default=0, help="seed of world and expert (default: 0)")
    parser.add_argument(
        "--grasp",
        choices=GRASP_MODES,
        default=GRASP,
        help="assisted (weld on closing) or physical (contact and friction only)",
    )
    parser.add_argument(
        "--skill", type=float, default=1.0, help="expert skill in [0, 1] (default: 1, the best)"
    )
    parser.add_argument(
        "--time-limit",
        type=float,
        default=TIME_LIMIT_S,
        metavar="S",
        help=f"give up after this many simulated seconds (default: {TIME_LIMIT_S:g})",
    )
    parser.add_argument("--video", type=Path, help="write an MP4 of the run from a fixed camera")
    parser.add_argument(
        "--video-size", default="640x360", metavar="WxH", help="video size (default: 640x360)"
    )
    parser.add_argument("--json", action="store_true", help="print one JSON object")
    parser.set_defaults(func=run)


def _video_size(text: str) -> tuple[int, int]:
    try:
        width, height = (int(v) for v in text.lower().split("x"))
    except ValueError:
        raise ConfigError(
            [f"--video-size = {text!r}: must be WIDTHxHEIGHT, e.g. 640x360"]
        ) from None
    if not (64 <= width <= 3840 and 64 <= height <= 2160 and width % 2 == 0 and height % 2 == 0):
        raise ConfigError(
            [f"--video-size = {text!r}: width 64..3840 and height 64..2160, both even"]
        )
    return width, height


def _check(args: argparse.Namespace) -> None:
    problems = []
    if not (math.isfinite(args.skill) and 0.0 <= args.skill <= 1.0):
        problems.append(f"--skill = {args.skill:g}: must be between 0 and 1")
    problems += check_as(TaskConfig, "time_limit_s", "--time-limit", args.time_limit)
    if args.video is not None and Path(args.video).suffix.lower() != ".mp4":
        problems.append(f"--video = {str(args.video)!r}: must be a file name ending in .mp4")
    if problems:
        raise ConfigError(problems)


class _Progress:
    """One status line on stderr, refreshed every simulated second when stderr is a terminal."""

    def __init__(self, time_limit_s: float) -> None:
        self._limit = time_limit_s
        self._next = 1.0
        self._live = sys.stderr.isatty()

    def __call__(self, sim: Simulation) -> None:
        if self._live and sim.time >= self._next:
            self._next += 1.0
            print(f"\r  simulating {sim.time:5.1f} / {self._limit:g} s", end="", file=sys.stderr)

    def done(self) -> None:
        if self._live:
            print("\r" + " " * 40 + "\r", end="", file=sys.stderr)


def run(args: argparse.Namespace) -> int:
    _check(args)
    size = _video_size(args.video_size) if args.video is not None else None
    from workcell.control.simulation import Simulation  # noqa: PLC0415
    from workcell.expert import ExpertConfig  # noqa: PLC0415
    from workcell.tasks.box_transfer.episode import deliver_one_box  # noqa: PLC0415
    from workcell.tasks.box_transfer.task import BoxTransfer  # noqa: PLC0415
    from workcell.tasks.elements.expert import ExpertOperator  # noqa: PLC0415

    sim = Simulation(WorldConfig(grasp=args.grasp), BoxTransfer().scene())
    expert = ExpertOperator(ExpertConfig(skill=args.skill), seed=args.seed)
    progress = _Progress(args.time_limit)
    if size is None:
        result = deliver_one_box(sim, expert, args.seed, args.time_limit, observer=progress)
    else:
        from workcell.cli.video_recorder import VideoRecorder  # noqa: PLC0415

        with VideoRecorder(sim, args.video, size, VIDEO_FPS) as recorder:

            def observe(s: Simulation) -> None:
                progress(s)
                recorder(s)

            result = deliver_one_box(sim, expert, args.seed, args.time_limit, observer=observe)
    progress.done()
    summary = {
        "delivered": result.delivered,
        "sim_time_s": round(result.sim_time_s, 3),
        "real_time_factor": round(result.real_time_factor, 1),
    }
    if args.json:
        print(json.dumps(summary))
    else:
        verdict = "delivered" if result.delivered else "NOT delivered"
        print(
            f"box {verdict} after {result.sim_time_s:.2f} s of simulated time "
            f"(grasp {args.grasp}, seed {args.seed}); "
            f"simulation ran at {result.real_time_factor:.1f}x real time"
        )
        if args.video is not None:
            print(f"video: {args.video}")
    return 0

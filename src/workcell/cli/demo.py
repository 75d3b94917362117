"""``workcell demo``: a task's autonomous expert does one trial, headless, optionally on video.

Its ``--json`` object: ``task``, ``world`` (null for the default world), ``outcome``,
``success``, ``stage`` (the furthest the trial reached), ``sim_time_s``,
``real_time_factor``, and ``delivered``, the same as ``success``: the one verdict the
command printed before it ran other tasks than box transfer, kept for scripts that read
it."""

from __future__ import annotations

import argparse
import dataclasses
import json
import math
import sys
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING

from workcell.cli.task_options import add_task_arguments
from workcell.errors import ConfigError
from workcell.session.config import TaskConfig
from workcell.settings import check_as, declared_default
from workcell.sim.config import GRASP_MODES, WorldConfig

if TYPE_CHECKING:
    from workcell.cli.command import Subparsers
    from workcell.control.simulation import Simulation
    from workcell.task.one_trial import OneTrialResult

VIDEO_FPS = 30
TIME_LIMIT_S: float = declared_default(TaskConfig, "time_limit_s")
GRASP: str = declared_default(WorldConfig, "grasp")


def register(subparsers: Subparsers) -> None:
    parser = subparsers.add_parser(
        "demo",
        help="watch a task's autonomous expert do one trial",
        description=(
            "Run a task's scripted expert for one trial (box transfer: one box) in the "
            "default workcell or one of the task's worlds, headless, and print how it ended, "
            "the furthest stage it reached, the simulated time it took and the real-time "
            "factor of the simulation loop."
        ),
    )
    add_task_arguments(parser)
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
        help=f"give up after this many simulated seconds (default: {TIME_LIMIT_S:g}; a task "
        "that needs longer raises it, palletize to 180)",
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
    from workcell.task.one_trial import run_one_trial  # noqa: PLC0415
    from workcell.tasks.registry import DEFAULT_TASK, load_task  # noqa: PLC0415
    from workcell.tasks.worlds import randomization  # noqa: PLC0415

    task = load_task(args.task or DEFAULT_TASK, "--task")
    world = WorldConfig(grasp=args.grasp)
    if args.world is not None:
        world = dataclasses.replace(world, randomization=randomization(task.worlds[args.world]))
    sim = Simulation(world, task.scene())
    expert = task.expert(ExpertConfig(skill=args.skill))
    progress = _Progress(max(args.time_limit, task.least_time_limit_s))

    def trial(observer: Callable[[Simulation], None]) -> OneTrialResult:
        return run_one_trial(
            sim, expert, args.seed, args.time_limit, kind=task.name, observer=observer
        )

    if size is None:
        result = trial(progress)
    else:
        from workcell.cli.video_recorder import VideoRecorder  # noqa: PLC0415

        with VideoRecorder(sim, args.video, size, VIDEO_FPS) as recorder:

            def observe(s: Simulation) -> None:
                progress(s)
                recorder(s)

            result = trial(observe)
    progress.done()
    summary = {
        "task": task.name,
        "world": args.world,
        "outcome": result.outcome,
        "success": result.succeeded,
        "stage": result.stage,
        "sim_time_s": round(result.sim_time_s, 3),
        "real_time_factor": round(result.real_time_factor, 1),
        "delivered": result.succeeded,
    }
    if args.json:
        print(json.dumps(summary))
    else:
        print(
            f"{task.name}: {result.outcome} after {result.sim_time_s:.2f} s of simulated time, "
            f"furthest stage {result.stage} (world {args.world or 'default'}, grasp "
            f"{args.grasp}, seed {args.seed}); "
            f"simulation ran at {result.real_time_factor:.1f}x real time"
        )
        if args.video is not None:
            print(f"video: {args.video}")
    return 0

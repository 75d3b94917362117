"""``workcell render``: re-render recorded trials from a robot camera into MP4 videos."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import TYPE_CHECKING

from workcell.errors import ConfigError

if TYPE_CHECKING:
    from workcell.cli.command import Subparsers


def register(subparsers: Subparsers) -> None:
    parser = subparsers.add_parser(
        "render",
        help="re-render recorded trials from robot cameras into MP4 videos",
        description=(
            "Restore every recorded frame's MuJoCo state (base, joints, fingers, boxes) and "
            "render it from a robot camera at any size, one OUT/<trial>_<camera>.mp4 per "
            "trial at the session's frame rate. Each trial is first checked: the restored "
            "states must reproduce the recorded TCP poses within 1e-6 m."
        ),
    )
    parser.add_argument("--store", required=True, type=Path, metavar="PATH", help="a store")
    parser.add_argument(
        "--camera",
        required=True,
        metavar="NAME",
        help="head_cam, wrist_l_cam or wrist_r_cam (several: comma-separated)",
    )
    parser.add_argument("--size", default="320x240", metavar="WxH", help="default 320x240")
    parser.add_argument(
        "--trial",
        action="append",
        default=[],
        metavar="ID",
        help="render this trial only (repeatable; default: every trial with frames)",
    )
    parser.add_argument("--out", required=True, type=Path, metavar="DIR", help="video folder")
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from workcell.export.options import ImageSize, parse_cameras  # noqa: PLC0415

    problems: list[str] = []
    cameras: tuple[str, ...] = ()
    size = ImageSize()
    try:
        cameras = parse_cameras(args.camera, "--camera")
    except ConfigError as error:
        problems += error.problems
    try:
        size = ImageSize.parse(args.size)
    except ConfigError as error:
        problems += error.problems
    if problems:
        raise ConfigError(problems)
    from workcell.export.rendering import render_trials  # noqa: PLC0415

    results = render_trials(
        args.store, args.out, cameras, size, trial_ids=args.trial, progress=_progress
    )
    for result in results:
        for path in result.videos:
            print(f"{path}: {result.frames} frames, replay error {result.replay.position_m:.2g} m")
    frames = sum(r.frames for r in results) * len(cameras)
    seconds = sum(r.seconds for r in results)
    per_frame = 1000 * seconds / frames if frames else 0.0
    print(
        f"rendered {len(results)} trials, {frames} images at {size} in {seconds:.1f} s "
        f"({per_frame:.1f} ms per image)"
    )
    return 0


def _progress(line: str) -> None:
    print(line, file=sys.stderr, flush=True)

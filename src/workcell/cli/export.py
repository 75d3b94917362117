"""``workcell export``: write a store's records in an interchange format."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import TYPE_CHECKING

from workcell.errors import ConfigError

if TYPE_CHECKING:
    from workcell.cli.main import Subparsers

FORMATS = ("csv",)
PLANNED_FORMATS = ("lerobot", "hdf5", "rerun")
PROGRESS_STEPS = 10


def register(subparsers: Subparsers) -> None:
    parser = subparsers.add_parser(
        "export",
        help="export a store (CSV with the interchange contract's columns)",
        description=(
            "Write a store's sessions, trials, events and frames into a new directory: "
            "sessions.csv, trials.csv, events.csv, frames.csv, annotations.csv and "
            "manifest.json (parameters, thresholds, joint order, metric definitions and "
            "the sha256 of every file). Check it later with 'workcell verify --csv DIR'."
        ),
    )
    parser.add_argument(
        "--format", required=True, metavar="{" + ",".join(FORMATS) + "}", help="export format"
    )
    parser.add_argument("--store", required=True, type=Path, metavar="PATH", help="a store")
    parser.add_argument(
        "--out", required=True, type=Path, metavar="DIR", help="new or empty directory"
    )
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    if args.format in PLANNED_FORMATS:
        raise ConfigError(
            [f"--format {args.format}: {args.format} export is not available yet; use csv"]
        )
    if args.format not in FORMATS:
        raise ConfigError([f"--format {args.format!r}: must be one of {', '.join(FORMATS)}"])
    from workcell.record.export_csv import export_csv  # noqa: PLC0415

    manifest = export_csv(args.store, args.out, _Progress())
    files = manifest["files"]
    print(
        f"exported {files['sessions.csv']['rows']} sessions, {files['trials.csv']['rows']} "
        f"trials, {files['frames.csv']['rows']} frames to {args.out}"
    )
    return 0


class _Progress:
    """Prints how far the frames are, in tenths, to stderr when it is a terminal."""

    def __init__(self) -> None:
        self.shown = 0

    def __call__(self, done: int, total: int) -> None:
        if not sys.stderr.isatty() or total == 0:
            return
        step = done * PROGRESS_STEPS // total
        if step > self.shown:
            self.shown = step
            print(f"frames: {done}/{total}", file=sys.stderr)

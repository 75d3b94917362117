"""``workcell export``: write a store's records in an interchange or dataset format."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import TYPE_CHECKING

from workcell.errors import ConfigError

if TYPE_CHECKING:
    from workcell.cli.command import Subparsers
    from workcell.export.options import ExportOptions
    from workcell.export.selection import Selection

FORMATS = ("csv", "lerobot", "hdf5", "rerun")
DATASET_FORMATS = ("lerobot", "hdf5", "rerun")
"""Formats that export the selected trials (see workcell.export.selection)."""
CAMERA_FORMATS = ("lerobot", "hdf5")
"""Formats that render robot cameras from the recorded states."""
OPTION_FORMATS: dict[str, tuple[str, ...]] = {
    "--all": DATASET_FORMATS,
    "--audited": DATASET_FORMATS,
    "--successes": DATASET_FORMATS,
    "--task": DATASET_FORMATS,
    "--operator": DATASET_FORMATS,
    "--cameras": CAMERA_FORMATS,
    "--size": CAMERA_FORMATS,
    "--rerender": CAMERA_FORMATS,
}
PROGRESS_STEPS = 10


def register(subparsers: Subparsers) -> None:
    parser = subparsers.add_parser(
        "export",
        help="export a store (CSV, LeRobot v3.0 dataset, robomimic HDF5, Rerun recordings)",
        description=(
            "Write a store's records into a new or empty directory. csv: sessions.csv, "
            "trials.csv, events.csv, frames.csv, annotations.csv and manifest.json (check it "
            "later with 'workcell verify --csv DIR'). lerobot: a LeRobotDataset v3.0 (meta/, "
            "data/, videos/) with a provenance sidecar meta/workcell_provenance.parquet|json. "
            "hdf5: a robomimic-style workcell.hdf5 with masks for outcome and inclusion. "
            "rerun: one .rrd recording per trial for the Rerun viewer 0.26 (as LeRobot 0.4) and "
            "workcell_provenance.json. Dataset exports (lerobot, hdf5, rerun) take included "
            "trials only unless --all and refuse a store that fails 'workcell verify'. "
            "lerobot and hdf5 take --cameras from the trials' recorded camera videos "
            "('workcell collect --cameras') where they match, else render them from the "
            "recorded states; the progress lines and the provenance say which."
        ),
    )
    parser.add_argument(
        "--format", required=True, metavar="{" + ",".join(FORMATS) + "}", help="export format"
    )
    parser.add_argument("--store", required=True, type=Path, metavar="PATH", help="a store")
    parser.add_argument(
        "--out", required=True, type=Path, metavar="DIR", help="new or empty directory"
    )
    parser.add_argument(
        "--all",
        action="store_true",
        help="lerobot/hdf5/rerun: every closed trial, not only included ones (interrupted, "
        "excluded); the provenance marks each",
    )
    parser.add_argument(
        "--audited",
        action="store_true",
        help="lerobot/hdf5/rerun: the trials the audit keeps (valid, no quality flag; its "
        "detectors, dispositions and reviewers' decisions) instead of the store's included "
        "trials",
    )
    parser.add_argument(
        "--successes",
        action="store_true",
        help="lerobot/hdf5/rerun: successful trials only (for imitation learning)",
    )
    parser.add_argument(
        "--task",
        action="append",
        metavar="NAME",
        help="lerobot/hdf5/rerun: only the sessions that ran this task ('workcell tasks'; "
        "repeatable)",
    )
    parser.add_argument(
        "--operator",
        action="append",
        metavar="ID",
        help="lerobot/hdf5/rerun: only the sessions of this operator id (repeatable; "
        "'workcell audit' lists them)",
    )
    parser.add_argument(
        "--cameras",
        metavar="NAMES",
        help="lerobot/hdf5: images of these robot cameras, comma-separated (head_cam, "
        "wrist_l_cam, wrist_r_cam): a trial's recorded video of the camera when it has the "
        "size asked for (copied, after checking its sha256 and frame count), else rendered "
        "from the recorded states",
    )
    parser.add_argument(
        "--size",
        metavar="WxH",
        help="lerobot/hdf5: camera image size (even numbers; default: the size the trials' "
        "camera videos were recorded at, else 320x240)",
    )
    parser.add_argument(
        "--rerender",
        action="store_true",
        help="lerobot/hdf5: render every camera image from the recorded states, even where "
        "the trial's camera videos were recorded",
    )
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    if args.format not in FORMATS:
        raise ConfigError([f"--format {args.format!r}: must be one of {', '.join(FORMATS)}"])
    _refuse_options_that_do_not_apply(args)
    if args.format == "csv":
        return _run_csv(args)
    options = dataset_options(args)
    from workcell.export.hdf5_export import export_hdf5  # noqa: PLC0415
    from workcell.export.lerobot_export import export_lerobot  # noqa: PLC0415
    from workcell.export.rerun_export import export_rerun  # noqa: PLC0415

    export = {"lerobot": export_lerobot, "hdf5": export_hdf5, "rerun": export_rerun}[args.format]
    summary = export(args.store, args.out, options, _print_progress)
    rate = summary.frames / summary.seconds if summary.seconds > 0 else float("inf")
    videos = ""
    if summary.videos:
        videos = (
            f", {_count(summary.videos, 'camera stream')} "
            f"({_count(summary.recorded_videos, 'episode video')} from the recordings, "
            f"{summary.rendered_videos} rendered)"
        )
    print(
        f"exported {_count(summary.episodes, 'episode')}, {summary.frames} frames{videos} as "
        f"{args.format} to {args.out} ({summary.seconds:.1f} s, {rate:.0f} frames/s)"
    )
    if summary.selection is not None:
        print(f"  {selection_text(summary.selection)}")
    return 0


def selection_text(selection: Selection) -> str:
    """What a dataset export kept and left out, per reason: ``kept 6 of 11 closed trials
    (4 success, 2 timeout; 2 of them practice); left out 5: 4 incomplete: interrupted
    (operator_stop), 1 without frames``."""
    from collections import Counter  # noqa: PLC0415

    kept = selection.episodes
    outcomes = Counter(e.trial.outcome for e in kept)
    parts = ", ".join(f"{n} {outcome}" for outcome, n in outcomes.most_common())
    practice = sum(e.trial.mode == "practice" for e in kept)
    if practice:
        parts += f"; {practice} of them practice"
    left = sum(selection.left_out.values())
    reasons = ", ".join(f"{n} {reason}" for reason, n in selection.left_out.items())
    return f"kept {len(kept)} of {selection.closed} closed trials ({parts}); " + (
        f"left out {left}: {reasons}" if left else "left out none"
    )


def dataset_options(args: argparse.Namespace) -> ExportOptions:
    """The dataset export options of the command line (ConfigError on bad values)."""
    from workcell.export.options import ExportOptions, ImageSize, parse_cameras  # noqa: PLC0415

    problems: list[str] = []
    cameras: tuple[str, ...] = ()
    size = None
    try:
        cameras = parse_cameras(args.cameras) if args.cameras is not None else ()
    except ConfigError as error:
        problems += error.problems
    try:
        size = ImageSize.parse(args.size) if args.size is not None else None
    except ConfigError as error:
        problems += error.problems
    if args.size is not None and not cameras:
        problems.append("--size applies to camera images: give --cameras too")
    if args.rerender and not cameras:
        problems.append("--rerender applies to camera images: give --cameras too")
    if problems:
        raise ConfigError(problems)
    return ExportOptions(
        include_all=args.all,
        audited=args.audited,
        successes_only=args.successes,
        tasks=tuple(args.task or ()),
        operators=tuple(args.operator or ()),
        cameras=cameras,
        size=size,
        rerender=args.rerender,
    )


def _refuse_options_that_do_not_apply(args: argparse.Namespace) -> None:
    problems = [
        f"{option}: applies to the {_listed(formats)} formats"
        for option, formats in OPTION_FORMATS.items()
        if getattr(args, option.removeprefix("--")) not in (None, False)
        and args.format not in formats
    ]
    if problems:
        raise ConfigError(problems)


def _count(n: int, noun: str) -> str:
    """``1 camera stream``, ``3 camera streams``."""
    return f"{n} {noun}{'' if n == 1 else 's'}"


def _listed(names: tuple[str, ...]) -> str:
    """``a, b and c``."""
    return " and ".join(names) if len(names) < 3 else f"{', '.join(names[:-1])} and {names[-1]}"


def _run_csv(args: argparse.Namespace) -> int:
    from workcell.record.export_csv import export_csv  # noqa: PLC0415

    manifest = export_csv(args.store, args.out, _Progress())
    files = manifest["files"]
    print(
        f"exported {files['sessions.csv']['rows']} sessions, {files['trials.csv']['rows']} "
        f"trials, {files['frames.csv']['rows']} frames to {args.out}"
    )
    return 0


def _print_progress(line: str) -> None:
    print(line, file=sys.stderr, flush=True)


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

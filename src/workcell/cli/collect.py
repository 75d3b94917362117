"""``workcell collect``: run a session headless with the autonomous expert at full speed."""

from __future__ import annotations

import argparse
import math
from pathlib import Path
from typing import TYPE_CHECKING, Any

from workcell import checks
from workcell.cli.collect_operator import (
    POLICY_PREFIX,
    corrector,
    driver,
    policy_checkpoint,
    with_operator_id,
)
from workcell.cli.task_options import add_task_arguments, task_flags
from workcell.errors import ConfigError, WorkcellError
from workcell.expert.skill import MAX_BASE_NOISE
from workcell.intervene.rules import CORRECTORS, SECONDS, CorrectorRules, within_seconds

if TYPE_CHECKING:
    from workcell.cli.command import Subparsers

DEFAULT_STORE = "workcell.sqlite"


def register(subparsers: Subparsers) -> None:
    parser = subparsers.add_parser(
        "collect",
        help="run a session headless with the autonomous expert or a learned policy",
        description=(
            "Run practice, collection or challenge trials headless at full speed with the "
            "scripted expert or a learned policy (policy:PATH, a LeRobot checkpoint; needs "
            "the learn extra), and print one row per trial as it ends. Settings come from the "
            "defaults, then --config FILE, then --set KEY=VALUE, then the flags below; "
            "'workcell config --defaults' lists every setting."
        ),
    )
    parser.add_argument(
        "--operator",
        default="expert",
        metavar="expert|policy:PATH",
        help="who drives: the scripted expert (default), or the LeRobot policy at PATH "
        "(a pretrained_model directory, or a 'workcell train' output)",
    )
    parser.add_argument(
        "--corrector",
        choices=CORRECTORS,
        help="a scripted corrector stands in for a person watching --operator: the task's "
        "expert takes over when the trial's stage stalls or a grasped box is dropped, drives "
        "to the next stage and hands back, recorded as a live correction "
        "(docs/intervention.md)",
    )
    parser.add_argument(
        "--stall-s",
        type=float,
        metavar="S",
        help=f"with --corrector: take over after S s without a new stage (default: "
        f"{CorrectorRules().stall_s:g})",
    )
    add_task_arguments(parser)
    parser.add_argument("--mode", choices=("practice", "collection", "challenge"))
    parser.add_argument(
        "--trials",
        type=int,
        help="stop after N trials (a challenge campaign cut short ends incomplete)",
    )
    parser.add_argument("--config", type=Path, metavar="FILE", help="session settings (TOML)")
    parser.add_argument("--seed", type=int, help="session seed (default: 0)")
    parser.add_argument("--skill", type=float, default=1.0, help="expert skill in [0, 1]")
    parser.add_argument(
        "--base-noise",
        type=float,
        default=0.0,
        metavar="M_S",
        help="push the expert's base off its course while it drives (standard deviation, "
        f"m/s, 0 to {MAX_BASE_NOISE:g}), so that its demonstrations show it steering back "
        "(noise injection as DART; default 0: none)",
    )
    parser.add_argument(
        "--operator-id",
        help="operator id stored with the session (default: expert, expert-skill<X>, "
        "expert-noise<V> with --base-noise, or the "
        "policy's type, run and weights hash; with --corrector, the corrector: who watched)",
    )
    parser.add_argument(
        "--condition",
        metavar="NAME",
        help="study condition stored with the session, compared by 'workcell audit --by "
        "condition' (default: none)",
    )
    parser.add_argument(
        "--set",
        action="append",
        default=[],
        metavar="KEY=VALUE",
        help="override one setting, e.g. --set world.box.mass=0.5 (repeatable)",
    )
    parser.add_argument(
        "--store",
        type=Path,
        default=Path(DEFAULT_STORE),
        metavar="PATH",
        help=f"SQLite store to record into (default: {DEFAULT_STORE}; created if absent)",
    )
    parser.add_argument(
        "--no-store", action="store_true", help="do not record (only print the trials)"
    )
    parser.add_argument(
        "--writer",
        choices=("process", "inline"),
        default="process",
        help="who writes the store: a writer process on another core (default), or this "
        "process (what --workers uses, as its workers fill the cores already)",
    )
    parser.add_argument(
        "--key",
        type=Path,
        metavar="FILE",
        help="sign the store's hash chain with the secret in FILE (at least 16 bytes), so "
        "that 'workcell verify --key FILE' detects a chain recomputed without it",
    )
    parser.add_argument(
        "--cameras",
        metavar="NAMES",
        help="record these cameras at the frame rate, e.g. head_cam,wrist_l_cam,wrist_r_cam "
        "(MP4 per trial in <store>.media/)",
    )
    parser.add_argument(
        "--camera-size", default="128x128", metavar="WxH", help="camera image size (128x128)"
    )
    parser.add_argument(
        "--camera-quality",
        default="fast",
        metavar="fast|fine",
        help="fast (default: no multisampling, coarser curves and floor grid, about six "
        "times as fast per frame on a software renderer) or fine (as the model asks)",
    )
    parser.add_argument(
        "--workers",
        type=int,
        default=1,
        help="run K worker processes, one store shard each, merged into --store at the end",
    )
    parser.add_argument(
        "--ray",
        metavar="ADDRESS",
        help="run the --workers as Ray tasks on the cluster at ADDRESS ('local': start one here)",
    )
    parser.add_argument("--json", action="store_true", help="one JSON object per trial per line")
    parser.add_argument(
        "--verbose",
        action="store_true",
        help="show what torch and LeRobot print while a policy loads (dropped by default, "
        "so that the table comes first)",
    )
    parser.set_defaults(func=run)


def _check(args: argparse.Namespace) -> list[str]:
    problems = []
    if args.operator != "expert" and not (
        args.operator.startswith(POLICY_PREFIX) and len(args.operator) > len(POLICY_PREFIX)
    ):
        problems.append(f"--operator = {args.operator!r}: must be expert or policy:PATH")
    if args.operator.startswith(POLICY_PREFIX) and (args.workers > 1 or args.ray):
        problems.append("--operator policy:PATH: runs in this process; drop --workers/--ray")
    if args.corrector is not None and (args.workers > 1 or args.ray):
        problems.append("--corrector: watches the session in this process; drop --workers/--ray")
    if args.stall_s is not None and args.corrector is None:
        problems.append("--stall-s: the corrector's rule; it needs --corrector expert")
    if args.stall_s is not None and not within_seconds(args.stall_s):
        low, high = SECONDS
        problems.append(f"--stall-s = {args.stall_s:g}: must be {low:g} to {high:g} seconds")
    if args.trials is not None and not 1 <= args.trials <= 100_000:
        problems.append(f"--trials = {args.trials}: must be 1 to 100000")
    if not (math.isfinite(args.skill) and 0.0 <= args.skill <= 1.0):
        problems.append(f"--skill = {args.skill:g}: must be between 0 and 1")
    if not (math.isfinite(args.base_noise) and 0.0 <= args.base_noise <= MAX_BASE_NOISE):
        problems.append(f"--base-noise = {args.base_noise:g}: must be 0 to {MAX_BASE_NOISE:g} m/s")
    elif args.base_noise > 0 and (args.operator != "expert" or args.corrector is not None):
        problems.append(
            "--base-noise: perturbs the expert's demonstrations; it needs --operator "
            "expert and no --corrector"
        )
    if not 1 <= args.workers <= 64:
        problems.append(f"--workers = {args.workers}: must be 1 to 64")
    if (args.workers > 1 or args.ray) and args.no_store:
        problems.append("--workers: workers write store shards; it cannot go with --no-store")
    if args.key is not None and args.no_store:
        problems.append("--key: signs what is recorded; it cannot go with --no-store")
    return problems


def _video_rate_problems(rate_hz: float) -> list[str]:
    """--cameras records one video frame per recorded frame: the frame rate must be one a
    video can have (checked here, not when the first trial's video starts)."""
    from workcell.render.video import MAX_FPS  # noqa: PLC0415

    if 1.0 <= rate_hz <= MAX_FPS:
        return []
    allowed = (
        f"--cameras records a video frame per recorded frame: must be between 1 and {MAX_FPS} Hz"
    )
    return [checks.problem("recording.sampling_rate_hz", rate_hz, allowed)]


def run(args: argparse.Namespace) -> int:
    problems = _check(args)
    from workcell.session.load import resolve_session_config  # noqa: PLC0415

    flags: dict[str, Any] = {"task.mode": args.mode, "seed": args.seed}
    flags["operator_id"] = args.operator_id
    flags["condition"] = args.condition
    if args.mode == "collection" or (args.mode is None and args.trials is not None):
        flags["task.trials"] = args.trials
    config = None
    try:
        flags.update(task_flags(args, args.set))
        config = resolve_session_config(args.config, args.set, flags)
        from workcell.tasks.registry import task_class  # noqa: PLC0415

        task_class(config.task.kind)  # an unknown task is refused before anything runs
    except ConfigError as error:
        problems += error.problems
    cameras = None
    if args.cameras is not None:
        from workcell.recording.media import CameraOptions  # noqa: PLC0415

        try:
            cameras = CameraOptions.parse(args.cameras, args.camera_size, args.camera_quality)
        except ConfigError as error:
            problems += error.problems
        if args.no_store:
            problems.append("--cameras: videos are recorded beside the store; drop --no-store")
        if config is not None:
            problems += _video_rate_problems(config.recording.sampling_rate_hz)
    checkpoint = None
    try:
        checkpoint = policy_checkpoint(args)
    except WorkcellError as error:
        problems.append(str(error))
    if problems or config is None:
        raise ConfigError(problems)
    config = with_operator_id(config, args, checkpoint)
    if args.workers > 1 or args.ray:
        from workcell.cli.parallel_collect import run_parallel  # noqa: PLC0415

        return run_parallel(args, config.seed, cameras)

    from workcell.cli.closed_output import EXIT_OUTPUT_CLOSED  # noqa: PLC0415
    from workcell.cli.collect_output import TrialPrinter  # noqa: PLC0415
    from workcell.recording.headless import headless_status, run_headless  # noqa: PLC0415
    from workcell.recording.recorded_session import (  # noqa: PLC0415
        RecordedSession,
        RecordedSessionConfig,
    )

    recorded = RecordedSessionConfig(
        session=config,
        driver=driver(args, checkpoint),
        store=None if args.no_store else args.store,
        writer=args.writer,
        key_file=args.key,
        cameras=cameras,
        max_trials=args.trials,
    )
    with RecordedSession.open(recorded) as session:
        printer = TrialPrinter(args.json)
        printer.header()
        runner = session.runner
        watch = corrector(args, session)

        def after_step() -> None:
            if watch is not None:
                watch.after_step()
            printer.progress(runner)

        signal_name = run_headless(session, printer.row, after_step, printer.check_output)
        printer.summary(runner)
        if session.recorder is not None and session.failure is None:
            printer.stored(args.store, session.session_id, session.frames_written)
    closed = EXIT_OUTPUT_CLOSED if printer.output_closed else 0
    return headless_status(session, signal_name, closed)

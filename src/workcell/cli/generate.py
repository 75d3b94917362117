"""``workcell generate``: many new demonstrations from a few recorded ones, in new worlds."""

from __future__ import annotations

import argparse
import math
import shutil
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

from workcell.cli.task_options import add_task_arguments, task_flags
from workcell.errors import ConfigError

if TYPE_CHECKING:
    from workcell.cli.command import Subparsers
    from workcell.generate.attempts import AttemptResult
    from workcell.generate.plan import GenerationPlan
    from workcell.session.config import SessionConfig

SLACK_S = 20.0
"""An attempt's time limit: its longest source trial's time and this much more (unless
``--set task.time_limit_s=...``): an attempt that lost its box ends as a timeout soon."""


def register(subparsers: Subparsers) -> None:
    parser = subparsers.add_parser(
        "generate",
        help="generate demonstrations in new worlds by replaying recorded source trials",
        description=(
            "Cut each successful source trial at its task's recorded stage boundaries (or, "
            "for a task of several boxes a trial, where the hands take and let go of each), "
            "and replay its segments, moved with the objects they act on, in new worlds "
            "drawn from --world: every attempt is a recorded trial in --store (operator "
            "generated-<hash of the source trial ids>), accepted when the task succeeded "
            "and still held a second later. The task's expert is never called. Every "
            "built-in task; a task of one's own that declares what generation needs "
            "(docs/tasks.md)."
        ),
    )
    parser.add_argument(
        "--source", type=Path, required=True, metavar="STORE", help="store of source trials"
    )
    parser.add_argument(
        "--source-operator",
        action="append",
        default=[],
        metavar="ID",
        help="replay only the trials of this operator id (repeatable; default: all)",
    )
    parser.add_argument(
        "--attempts",
        type=int,
        required=True,
        metavar="N",
        help="how many attempts: each a new world, a recorded trial and a session",
    )
    parser.add_argument("--seed", type=int, default=0, help="generation seed (default: 0)")
    parser.add_argument(
        "--store",
        type=Path,
        required=True,
        metavar="OUT",
        help="SQLite store every attempt is recorded in (created if absent)",
    )
    add_task_arguments(parser)
    parser.add_argument(
        "--config", type=Path, metavar="FILE", help="session settings (TOML) for the attempts"
    )
    parser.add_argument(
        "--set",
        action="append",
        default=[],
        metavar="KEY=VALUE",
        help="override one setting, e.g. --set world.box.mass=0.5 (repeatable)",
    )
    parser.add_argument(
        "--workers",
        type=int,
        default=1,
        metavar="W",
        help="W worker processes taking attempts from one queue, each into a shard, "
        "merged into --store at the end (default: 1, in this process)",
    )
    parser.add_argument(
        "--ray",
        metavar="local|ADDRESS",
        help="run the attempts as Ray tasks (5 attempts each, --workers at a time) on the "
        "cluster at ADDRESS ('local': start Ray here); shards merged into --store",
    )
    parser.set_defaults(func=run)


def _check(args: argparse.Namespace) -> list[str]:
    problems = []
    if not 1 <= args.attempts <= 1_000_000:
        problems.append(f"--attempts = {args.attempts}: must be 1 to 1000000")
    if not 1 <= args.workers <= 64:
        problems.append(f"--workers = {args.workers}: must be 1 to 64")
    if args.source.resolve() == args.store.resolve():
        problems.append(f"--store {args.store}: must not be the --source store")
    return problems


def run(args: argparse.Namespace) -> int:
    problems = _check(args)
    from workcell.session.load import resolve_session_config  # noqa: PLC0415

    flags: dict[str, Any] = {"task.mode": "collection", "task.trials": 1, "seed": args.seed}
    config = None
    try:
        flags.update(task_flags(args, args.set))
        config = resolve_session_config(args.config, args.set, flags)
        from workcell.tasks.registry import task_class  # noqa: PLC0415

        task_class(config.task.kind)
    except ConfigError as error:
        problems += error.problems
    if problems or config is None:
        raise ConfigError(problems)

    from workcell.generate.plan import GenerationPlan  # noqa: PLC0415
    from workcell.generate.references import references_for  # noqa: PLC0415
    from workcell.generate.source import load_sources  # noqa: PLC0415
    from workcell.tasks.registry import load_task  # noqa: PLC0415

    task = load_task(config.task.kind)
    references = references_for(task)
    sources = load_sources(args.source, config.task.kind, args.source_operator)
    plan = GenerationPlan.of(config.task.kind, sources, references)
    config = _with_time_limit(config, plan, args.set)
    return _generate(args, plan, config)


def _with_time_limit(
    config: SessionConfig, plan: GenerationPlan, overrides: list[str]
) -> SessionConfig:
    import dataclasses  # noqa: PLC0415

    if any(o.startswith("task.time_limit_s=") for o in overrides):
        return config
    longest = max(float(s.t[-1]) for s in plan.sources)
    limit = min(config.task.time_limit_s, math.ceil(longest + SLACK_S))
    return dataclasses.replace(config, task=dataclasses.replace(config.task, time_limit_s=limit))


def _generate(args: argparse.Namespace, plan: GenerationPlan, config: SessionConfig) -> int:
    from workcell.generate.tally import Tally  # noqa: PLC0415
    from workcell.recording.shutdown import ShutdownSignals, exit_status  # noqa: PLC0415
    from workcell.tasks import world_of  # noqa: PLC0415
    from workcell.tasks.registry import load_task  # noqa: PLC0415

    world = world_of(load_task(config.task.kind).worlds, config.world.randomization)
    print(
        f"generating {args.attempts} attempts of {config.task.kind} in world {world} from "
        f"{len(plan.sources)} source trials as operator {plan.operator_id} into {args.store}",
        flush=True,
    )
    tally = Tally()
    began = time.monotonic()

    def on_attempt(result: AttemptResult) -> None:
        tally.add(result)
        verdict = "accepted" if result.accepted else f"rejected: {result.reason}"
        print(
            f"attempt {result.attempt:5d}  {result.outcome:9s} {result.stage:10s} {verdict}  "
            f"| {tally.attempts}/{args.attempts} done, {tally.rate()}",
            flush=True,
        )

    with ShutdownSignals() as shutdown:
        if args.workers > 1 or args.ray:
            _in_workers(args, plan, config, on_attempt, lambda: shutdown.requested is not None)
        else:
            from workcell.generate.attempts import run_attempt  # noqa: PLC0415

            def stop() -> Literal["application_quit"] | None:
                return "application_quit" if shutdown.requested is not None else None

            for attempt in range(args.attempts):
                if shutdown.requested is not None:
                    break
                result = run_attempt(plan, config, attempt, args.store, stop)
                if result is not None:
                    on_attempt(result)
    wall = time.monotonic() - began
    print(
        f"{tally.attempts} attempts, {tally.rate()}; false successes caught by the re-check: "
        f"{tally.false_successes}; rejected: {tally.rejections()}; "
        f"{tally.per_cpu_hour():.0f} attempts per CPU-hour ({wall:.0f} s wall)"
    )
    print(f"recorded in {args.store} as operator {plan.operator_id}")
    return 0 if shutdown.requested is None else exit_status(shutdown.requested)


def _in_workers(
    args: argparse.Namespace,
    plan: GenerationPlan,
    config: SessionConfig,
    on_attempt: Callable[[AttemptResult], None],
    should_stop: Callable[[], bool],
) -> None:
    from workcell.generate.pool import run_pool  # noqa: PLC0415
    from workcell.record.merge import merge_stores  # noqa: PLC0415

    store = Path(args.store)
    shard_dir = store.with_name(f"{store.name}.shards") / time.strftime("run-%Y%m%d-%H%M%S")
    shard_dir.mkdir(parents=True, exist_ok=False)
    attempts = range(args.attempts)
    if args.ray:
        from workcell.generate.ray_pool import run_ray  # noqa: PLC0415

        shards = run_ray(
            args.ray,
            plan,
            config,
            attempts,
            args.workers,
            shard_dir=shard_dir,
            on_attempt=on_attempt,
            should_stop=should_stop,
        )
    else:
        shards = run_pool(
            plan,
            config,
            attempts,
            args.workers,
            shard_dir,
            on_attempt=on_attempt,
            should_stop=should_stop,
        )
    if shards:
        merge_stores(shards, store, progress=lambda m: print(m, file=sys.stderr))
    shutil.rmtree(shard_dir)
    if not any(shard_dir.parent.iterdir()):
        shard_dir.parent.rmdir()

"""``workcell collect --workers K``: K worker processes, one store shard each, merged."""

from __future__ import annotations

import argparse
import json
import shutil
import sys
import time
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

from workcell.cli.closed_output import EXIT_OUTPUT_CLOSED
from workcell.cli.collect_output import TrialPrinter, trial_json
from workcell.errors import WorkcellError
from workcell.recording.shutdown import exit_status

if TYPE_CHECKING:
    from workcell.recording.media import CameraOptions
    from workcell.scale.plan import WorkerPlan
    from workcell.scale.worker import WorkerJob
    from workcell.task.runner import TrialResult


def worker_jobs(
    args: argparse.Namespace, plans: Sequence[WorkerPlan], cameras: CameraOptions | None
) -> list[tuple[int, WorkerJob]]:
    """Each worker's job: the session settings resolved as ``workcell collect`` resolves
    them, with the worker's seed and share of the trials."""
    from workcell.cli.collect_operator import with_operator_id  # noqa: PLC0415
    from workcell.expert.skill import ExpertConfig  # noqa: PLC0415
    from workcell.recording.drivers import ExpertDriver  # noqa: PLC0415
    from workcell.scale.worker import WorkerJob  # noqa: PLC0415
    from workcell.session.load import resolve_session_config  # noqa: PLC0415

    jobs = []
    for plan in plans:
        flags: dict[str, Any] = {"task.mode": args.mode, "seed": plan.seed}
        flags["operator_id"] = args.operator_id
        if args.mode == "collection" or (args.mode is None and plan.trials is not None):
            flags["task.trials"] = plan.trials
        config = resolve_session_config(args.config, args.set, flags)
        job = WorkerJob(
            config=with_operator_id(config, args, None),
            shard=plan.shard,
            trials=plan.trials,
            skill=args.skill,
            key_file=args.key,
            cameras=cameras,
            driver=ExpertDriver(ExpertConfig(skill=args.skill, base_noise=args.base_noise)),
        )
        jobs.append((plan.worker, job))
    return jobs


def run_parallel(args: argparse.Namespace, seed: int, cameras: CameraOptions | None) -> int:
    from workcell.record.chain import ChainKey  # noqa: PLC0415
    from workcell.record.merge import merge_stores  # noqa: PLC0415
    from workcell.recording.shutdown import ShutdownSignals  # noqa: PLC0415
    from workcell.scale.plan import plan_workers  # noqa: PLC0415
    from workcell.scale.processes import run_local_workers  # noqa: PLC0415

    store = Path(args.store)
    shard_dir = store.with_name(f"{store.name}.shards") / time.strftime("run-%Y%m%d-%H%M%S")
    shard_dir.mkdir(parents=True, exist_ok=False)
    plans = plan_workers(args.workers, seed, args.trials, shard_dir)
    jobs = worker_jobs(args, plans, cameras)
    printer = TrialPrinter(args.json)
    where = f"Ray tasks on {args.ray}" if args.ray else "worker processes"
    print(f"{len(plans)} {where} writing shards in {shard_dir}", file=sys.stderr)
    counts = {"trials": 0, "successes": 0}

    def on_trial(worker: int, result: TrialResult) -> None:
        row = trial_json(result)
        counts["trials"] += 1
        counts["successes"] += row.get("outcome") == "success"
        if args.json:
            printer.out(json.dumps({"worker": worker, **row}))
        else:
            printer.out(
                f"worker {worker:2d}  trial {row['trial_index']:4d}  {row['outcome']:11s}  "
                f"boxes {row['boxes_delivered']}/{row['required_boxes']}  "
                f"score {row['score']:4d}  {row['elapsed_s']:7.2f} s"
            )

    with ShutdownSignals() as shutdown:
        if args.ray:
            from workcell.scale.ray_tasks import run_ray_workers  # noqa: PLC0415

            exits = run_ray_workers(args.ray, jobs, on_trial)
        else:
            # standard output closed (| head): the workers stop as on SIGINT
            def should_stop() -> bool:
                return shutdown.requested is not None or printer.check_output()

            exits = run_local_workers(jobs, on_trial, should_stop)
    for exit_ in exits:
        if exit_.returncode not in (0, 130, 143):  # stopped by SIGINT or SIGTERM
            print(
                f"worker {exit_.worker} died (exit {exit_.returncode}); its shard is recovered "
                f"like any crashed store. {exit_.stderr_tail}",
                file=sys.stderr,
            )
    shards = [p.shard for p in plans if p.shard.exists()]
    try:
        key = None if args.key is None else ChainKey.from_file(args.key)
        report = merge_stores(shards, store, progress=lambda m: print(m, file=sys.stderr), key=key)
    except WorkcellError:
        print(f"shards kept in {shard_dir}", file=sys.stderr)
        raise
    shutil.rmtree(shard_dir)
    if not any(shard_dir.parent.iterdir()):
        shard_dir.parent.rmdir()
    printer.note(
        f"{counts['trials']} trials, {counts['successes']} succeeded; merged {report.shards} "
        f"shards into {store}: {report.sessions} sessions, {report.trials} trials, "
        f"{report.frames} frames, verified"
    )
    if shutdown.requested is not None:
        return exit_status(shutdown.requested)
    if printer.output_closed:
        return EXIT_OUTPUT_CLOSED
    return 0 if all(e.returncode == 0 for e in exits) else 1

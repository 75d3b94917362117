"""``workcell collect --workers K``: K worker processes, one store shard each, merged."""

from __future__ import annotations

import argparse
import json
import shutil
import sys
import time
from pathlib import Path
from typing import Any

from workcell.errors import WorkcellError

PASS_THROUGH = ("mode", "config", "skill", "operator_id", "cameras", "camera_size", "key")


def common_arguments(args: argparse.Namespace) -> list[str]:
    """The options every worker shares (seed, trials and store are per worker)."""
    common: list[str] = []
    for name in PASS_THROUGH:
        value = getattr(args, name)
        if value is not None:
            common += [f"--{name.replace('_', '-')}", str(value)]
    for override in args.set:
        common += ["--set", override]
    return common


def run_parallel(args: argparse.Namespace, seed: int) -> int:
    from workcell.record.merge import merge_stores  # noqa: PLC0415
    from workcell.record.shutdown import ShutdownSignals  # noqa: PLC0415
    from workcell.scale.plan import plan_workers  # noqa: PLC0415
    from workcell.scale.processes import run_local_workers  # noqa: PLC0415

    store = Path(args.store)
    shard_dir = store.with_name(f"{store.name}.shards") / time.strftime("run-%Y%m%d-%H%M%S")
    shard_dir.mkdir(parents=True, exist_ok=False)
    plans = plan_workers(args.workers, seed, args.trials, shard_dir)
    out = sys.stderr if args.json else sys.stdout
    where = f"Ray tasks on {args.ray}" if args.ray else "worker processes"
    print(f"{len(plans)} {where} writing shards in {shard_dir}", file=sys.stderr)
    counts = {"trials": 0, "successes": 0}

    def on_trial(worker: int, row: dict[str, Any]) -> None:
        counts["trials"] += 1
        counts["successes"] += row.get("outcome") == "success"
        if args.json:
            print(json.dumps({"worker": worker, **row}), flush=True)
        else:
            print(
                f"worker {worker:2d}  trial {row['trial_index']:4d}  {row['outcome']:11s}  "
                f"boxes {row['boxes_delivered']}/{row['required_boxes']}  "
                f"score {row['score']:4d}  {row['elapsed_s']:7.2f} s",
                flush=True,
            )

    with ShutdownSignals() as shutdown:
        if args.ray:
            from workcell.scale.ray_tasks import run_ray_workers  # noqa: PLC0415

            exits = run_ray_workers(args.ray, plans, common_arguments(args), on_trial)
        else:
            exits = run_local_workers(
                plans, common_arguments(args), on_trial, lambda: shutdown.requested is not None
            )
    for exit_ in exits:
        if exit_.returncode not in (0, 130, 143):  # stopped by SIGINT or SIGTERM
            print(
                f"worker {exit_.worker} died (exit {exit_.returncode}); its shard is recovered "
                f"like any crashed store. {exit_.stderr_tail}",
                file=sys.stderr,
            )
    shards = [p.shard for p in plans if p.shard.exists()]
    try:
        report = merge_stores(shards, store, progress=lambda m: print(m, file=sys.stderr))
    except WorkcellError:
        print(f"shards kept in {shard_dir}", file=sys.stderr)
        raise
    shutil.rmtree(shard_dir)
    if not any(shard_dir.parent.iterdir()):
        shard_dir.parent.rmdir()
    print(
        f"{counts['trials']} trials, {counts['successes']} succeeded; merged {report.shards} "
        f"shards into {store}: {report.sessions} sessions, {report.trials} trials, "
        f"{report.frames} frames, verified",
        file=out,
    )
    if shutdown.requested is not None:
        from workcell.cli.collect import exit_status  # noqa: PLC0415

        return exit_status(shutdown.requested)
    return 0 if all(e.returncode == 0 for e in exits) else 1

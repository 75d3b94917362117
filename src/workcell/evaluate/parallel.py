"""``workcell evaluate --workers W``: each world's rollouts split over W worker processes.

The worlds run one after another; a world's shares (:meth:`EvaluationPlan.shares`) run at
once, each a :class:`~workcell.scale.worker.WorkerJob` recording into its own store shard
(the same workers as ``workcell collect --workers``); the shards are merged into the store
and verified at the end. The seeds are the shares' trial indices, so they are those of a
run in one process.
"""

from __future__ import annotations

import shutil
import sqlite3
import sys
import time
from collections.abc import Sequence
from pathlib import Path

from workcell.errors import WorkcellError
from workcell.evaluate.plan import Share
from workcell.evaluate.run import OnTrial, Ran
from workcell.recording.drivers import Driver
from workcell.scale.worker import WorkerJob
from workcell.session.config import SessionConfig
from workcell.task.runner import TrialResult

Planned = tuple[Share, SessionConfig]

STOPPED = (130, 143)
"""Exit statuses of a worker stopped by SIGINT or SIGTERM."""


def _session_ids(shard: Path) -> list[str]:
    with sqlite3.connect(f"file:{shard}?mode=ro", uri=True) as db:
        return [row[0] for row in db.execute("SELECT session_id FROM sessions")]


def run_in_workers(
    shares: Sequence[tuple[Share, SessionConfig]],
    driver: Driver,
    store: Path,
    on_trial: OnTrial,
) -> Ran:
    from workcell.record.merge import merge_stores  # noqa: PLC0415
    from workcell.recording.shutdown import ShutdownSignals  # noqa: PLC0415
    from workcell.scale.processes import run_local_workers  # noqa: PLC0415

    shard_dir = store.with_name(f"{store.name}.shards") / time.strftime("eval-%Y%m%d-%H%M%S")
    shard_dir.mkdir(parents=True, exist_ok=False)
    ran = Ran()
    shards: list[Path] = []
    worlds = list(dict.fromkeys(share.world for share, _ in shares))
    with ShutdownSignals() as shutdown:
        for world in worlds:
            mine = [(share, config) for share, config in shares if share.world == world]
            jobs: list[tuple[int, WorkerJob]] = []
            for share, config in mine:
                shard = shard_dir / f"{world}-{share.first:06d}.sqlite"
                shards.append(shard)
                job = WorkerJob(config, shard, trials=share.rollouts, driver=driver)
                jobs.append((len(jobs), job))

            def report(worker: int, result: TrialResult, mine: Sequence[Planned] = mine) -> None:
                on_trial(mine[worker][0], result)

            def stopping() -> bool:
                return shutdown.requested is not None

            exits = run_local_workers(jobs, report, stopping)
            for exit_ in exits:
                if exit_.returncode != 0 and exit_.returncode not in STOPPED:
                    ran.worker_deaths.append(
                        f"worker {exit_.worker} of world {world} ended with exit "
                        f"{exit_.returncode}; its shard is recovered like any crashed store. "
                        f"{exit_.stderr_tail}"
                    )
            if shutdown.requested is not None:
                ran.signal_name = shutdown.requested
                break
    existing = [shard for shard in shards if shard.exists()]
    try:
        if existing:
            merge_stores(existing, store)  # recovers a dead worker's shard first
    except WorkcellError:
        print(f"shards kept in {shard_dir}", file=sys.stderr)
        raise
    for shard in existing:
        ran.session_ids += _session_ids(shard)
    shutil.rmtree(shard_dir)
    if not any(shard_dir.parent.iterdir()):
        shard_dir.parent.rmdir()
    return ran

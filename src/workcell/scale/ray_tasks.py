"""Run the workers as Ray tasks, on an existing cluster or one started on this machine.

A task runs the same worker a local worker process runs (:func:`~workcell.scale.worker.
collect_shard`), into a shard in the task's own temporary folder, and returns the trials'
results, its exit status and the shard's bytes; the driver writes the shards beside the
target store and merges them like local shards. So a task behaves, records and fails
exactly like a local worker.
"""

from __future__ import annotations

import contextlib
import dataclasses
import io
import tempfile
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

from workcell.errors import WorkcellError
from workcell.scale.processes import WorkerExit
from workcell.scale.ray_cluster import start_ray
from workcell.scale.worker import EXIT_ERROR, WorkerJob, collect_shard
from workcell.task.runner import TrialResult


@dataclass(frozen=True)
class TaskResult:
    """What one Ray task hands back."""

    code: int
    trials: tuple[TrialResult, ...]
    shard: bytes
    """The shard's bytes (empty when none was written)."""
    stderr_tail: str


def _collect_in_task(job: WorkerJob) -> TaskResult:
    """Body of one Ray task: collect into a temporary shard, return results and the shard."""
    trials: list[TrialResult] = []
    err = io.StringIO()
    with tempfile.TemporaryDirectory() as folder:
        shard = Path(folder) / "shard.sqlite"
        with contextlib.redirect_stderr(err):
            try:
                code = collect_shard(dataclasses.replace(job, shard=shard), trials.append)
            except WorkcellError as error:
                print(f"workcell: error: {error}", file=err)
                code = EXIT_ERROR
        data = shard.read_bytes() if shard.exists() else b""
    return TaskResult(code, tuple(trials), data, err.getvalue()[-2000:])


def run_ray_workers(
    address: str,
    jobs: Sequence[tuple[int, WorkerJob]],
    on_trial: Callable[[int, TrialResult], None],
) -> list[WorkerExit]:
    """Run every ``(worker, job)`` as a Ray task (``address`` "local" starts Ray here);
    each task's shard is written to its job's ``shard`` here."""
    import ray  # noqa: PLC0415

    start_ray(address, max(1, len(jobs)))
    try:
        task = ray.remote(num_cpus=1)(_collect_in_task)
        pending = {task.remote(job): (worker, job) for worker, job in jobs}
        exits = []
        while pending:
            done, _ = ray.wait(list(pending), num_returns=1)
            worker, job = pending.pop(done[0])
            try:
                result: TaskResult = ray.get(done[0])
            except Exception as error:  # a task that died: report it, keep the others
                exits.append(WorkerExit(worker, -1, f"Ray task failed: {error}"))
                continue
            for trial in result.trials:
                on_trial(worker, trial)
            if result.shard:
                job.shard.write_bytes(result.shard)
            tail = "\n".join(result.stderr_tail.strip().splitlines()[-2:])
            exits.append(WorkerExit(worker, result.code, tail))
        return exits
    finally:
        ray.shutdown()

"""Run the workers as Ray tasks, on an existing cluster or one started on this machine.

A task runs the same ``workcell collect`` a worker process runs, into a shard in the task's
own temporary folder, and returns the trial rows it printed and the shard's bytes; the
driver writes the shards beside the target store and merges them like local shards. So a
task behaves, records and fails exactly like a local worker.
"""

from __future__ import annotations

import contextlib
import io
import json
import tempfile
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

from workcell.errors import WorkcellError
from workcell.scale.plan import WorkerPlan
from workcell.scale.processes import WorkerExit


class RayError(WorkcellError):
    """Ray could not be reached or a task could not run."""


def _collect_in_task(argv: list[str]) -> tuple[int, list[dict[str, Any]], bytes, str]:
    """Body of one Ray task: collect into a temporary shard, return rows and the shard."""
    from workcell.cli.main import main  # noqa: PLC0415

    with tempfile.TemporaryDirectory() as folder:
        shard = Path(folder) / "shard.sqlite"
        out, err = io.StringIO(), io.StringIO()
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            code = main([*argv, "--store", str(shard)])
        rows = [json.loads(line) for line in out.getvalue().splitlines() if line.startswith("{")]
        data = shard.read_bytes() if shard.exists() else b""
    return code, rows, data, err.getvalue()[-2000:]


def task_arguments(plan: WorkerPlan, common: Sequence[str]) -> list[str]:
    argv = ["collect", "--json", "--writer", "inline", *common, "--seed", str(plan.seed)]
    if plan.trials is not None:
        argv += ["--trials", str(plan.trials)]
    return argv


def run_ray_workers(
    address: str,
    plans: Sequence[WorkerPlan],
    common: Sequence[str],
    on_trial: Callable[[int, dict[str, Any]], None],
) -> list[WorkerExit]:
    """Run every plan as a Ray task (``address`` "local" starts Ray here)."""
    import ray  # noqa: PLC0415

    try:
        if address == "local":
            ray.init(num_cpus=max(1, len(plans)), include_dashboard=False, log_to_driver=False)
        else:
            ray.init(address=address, log_to_driver=False)
    except Exception as error:  # ray raises ConnectionError, RuntimeError, ValueError ...
        raise RayError(f"cannot connect to Ray at {address!r}: {error}") from None
    try:
        task = ray.remote(num_cpus=1)(_collect_in_task)
        pending = {task.remote(task_arguments(plan, common)): plan for plan in plans}
        exits = []
        while pending:
            done, _ = ray.wait(list(pending), num_returns=1)
            plan = pending.pop(done[0])
            try:
                code, rows, data, err = ray.get(done[0])
            except Exception as error:  # a task that died: report it, keep the others
                exits.append(WorkerExit(plan.worker, -1, f"Ray task failed: {error}"))
                continue
            for row in rows:
                on_trial(plan.worker, row)
            if data:
                plan.shard.write_bytes(data)
            tail = "\n".join(str(err).strip().splitlines()[-2:])
            exits.append(WorkerExit(plan.worker, int(code), tail))
        return exits
    finally:
        ray.shutdown()

"""Run the workers as local processes and stream what they print.

Each worker is ``python -m workcell collect --json --store SHARD --seed S ...``: the same
command a person runs, so a worker records, recovers and fails exactly like one.
"""

from __future__ import annotations

import json
import os
import selectors
import signal
import subprocess
import sys
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

from workcell.scale.plan import WorkerPlan


@dataclass(frozen=True)
class WorkerExit:
    worker: int
    returncode: int
    stderr_tail: str


def worker_command(plan: WorkerPlan, common: Sequence[str]) -> list[str]:
    # the workers fill the cores: each writes its shard itself, not through a writer process
    command = [sys.executable, "-m", "workcell", "collect", "--json", "--writer", "inline", *common]
    command += ["--store", str(plan.shard), "--seed", str(plan.seed)]
    if plan.trials is not None:
        command += ["--trials", str(plan.trials)]
    return command


def run_local_workers(
    plans: Sequence[WorkerPlan],
    common: Sequence[str],
    on_trial: Callable[[int, dict[str, Any]], None],
    should_stop: Callable[[], bool],
) -> list[WorkerExit]:
    """Run every plan as a process; ``on_trial(worker, row)`` for each trial row printed.

    When ``should_stop`` turns true, every worker gets SIGINT (it ends its trial as
    ``application_quit`` and closes its session)."""
    env = {**os.environ, "PYTHONUNBUFFERED": "1"}
    processes = {
        plan.worker: subprocess.Popen(
            worker_command(plan, common),
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
            env=env,
        )
        for plan in plans
    }
    selector = selectors.DefaultSelector()
    for worker, process in processes.items():
        assert process.stdout is not None
        selector.register(process.stdout, selectors.EVENT_READ, worker)
    open_streams = len(processes)
    stopping = False
    while open_streams:
        if not stopping and should_stop():
            stopping = True
            for process in processes.values():
                if process.poll() is None:
                    process.send_signal(signal.SIGINT)
        for key, _ in selector.select(timeout=0.2):
            line = key.fileobj.readline()  # type: ignore[union-attr]
            if not line:
                selector.unregister(key.fileobj)
                open_streams -= 1
                continue
            try:
                row = json.loads(line)
            except json.JSONDecodeError:
                continue
            on_trial(int(key.data), row)
    exits = []
    for worker, process in processes.items():
        _, err = process.communicate()
        tail = "\n".join(err.strip().splitlines()[-2:])
        exits.append(WorkerExit(worker, process.returncode, tail))
    return exits

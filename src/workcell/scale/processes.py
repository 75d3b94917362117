"""Run the workers as local processes and take their results as they come.

Each worker is ``python -m workcell.scale.worker``: it gets its :class:`~workcell.scale.
worker.WorkerJob` on standard input and sends each trial's result back on standard output
(length-prefixed pickles), so a worker records, recovers and fails like ``workcell
collect`` while nothing it prints is parsed.
"""

from __future__ import annotations

import os
import selectors
import signal
import subprocess
import sys
from collections.abc import Callable, Sequence
from dataclasses import dataclass

from workcell.recording.pipe_messages import MessageReader, send
from workcell.scale.worker import WorkerJob
from workcell.task.runner import TrialResult

WORKER_COMMAND = (sys.executable, "-m", "workcell.scale.worker")


@dataclass(frozen=True)
class WorkerExit:
    worker: int
    returncode: int
    stderr_tail: str


def run_local_workers(
    jobs: Sequence[tuple[int, WorkerJob]],
    on_trial: Callable[[int, TrialResult], None],
    should_stop: Callable[[], bool],
) -> list[WorkerExit]:
    """Run every ``(worker, job)`` as a process; ``on_trial(worker, result)`` for each
    trial as it ends.

    When ``should_stop`` turns true, every worker gets SIGINT (it ends its trial as
    ``application_quit`` and closes its session)."""
    env = {**os.environ, "PYTHONUNBUFFERED": "1"}
    processes: dict[int, subprocess.Popen[bytes]] = {}
    for worker, job in jobs:
        process = subprocess.Popen(
            WORKER_COMMAND,
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            env=env,
        )
        assert process.stdin is not None
        send(process.stdin, job)
        process.stdin.close()
        processes[worker] = process
    selector = selectors.DefaultSelector()
    for worker, process in processes.items():
        assert process.stdout is not None
        reader = MessageReader(process.stdout.fileno())
        selector.register(process.stdout, selectors.EVENT_READ, (worker, reader))
    open_streams = len(processes)
    stopping = False
    while open_streams:
        if not stopping and should_stop():
            stopping = True
            for process in processes.values():
                if process.poll() is None:
                    process.send_signal(signal.SIGINT)
        for key, _ in selector.select(timeout=0.2):
            worker, reader = key.data
            for message in reader.wait(0.0):
                if message is None:  # the worker closed its end: it is done
                    selector.unregister(key.fileobj)
                    open_streams -= 1
                elif isinstance(message, TrialResult):
                    on_trial(worker, message)
    exits = []
    for worker, process in processes.items():
        assert process.stdout is not None and process.stderr is not None
        err = process.stderr.read().decode(errors="replace")
        process.wait()
        process.stdout.close()
        process.stderr.close()
        tail = "\n".join(err.strip().splitlines()[-2:])
        exits.append(WorkerExit(worker, process.returncode, tail))
    return exits

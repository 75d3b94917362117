"""One scale-out worker: a whole session recorded into its own store shard.

A worker receives a :class:`WorkerJob` (frozen and picklable: the session configuration
already resolved, seed and trials the worker's own) and hands back each trial's
:class:`~workcell.task.runner.TrialResult` as it ends; it records, recovers and fails like
``workcell collect --writer inline`` (the same loop, :mod:`workcell.recording.headless`).
Run as a process (``python -m workcell.scale.worker``) it reads its job from standard
input and writes its results to standard output, both as length-prefixed pickles
(:mod:`workcell.recording.pipe_messages`); SIGINT or SIGTERM end its trial as
``application_quit`` and its exit status is the shells' (130, 143).
"""

from __future__ import annotations

import os
import sys
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from workcell.errors import WorkcellError
from workcell.recording.media import CameraOptions
from workcell.session.config import SessionConfig
from workcell.task.runner import TrialResult

EXIT_STORAGE = 1
"""The recording failed (disk full, I/O error): the shard holds what came before."""
EXIT_ERROR = 2
"""The job could not start (a bad setting, a store that cannot be opened)."""


@dataclass(frozen=True)
class WorkerJob:
    """Everything a worker needs: the session, who drives it and where it is recorded."""

    config: SessionConfig
    """The session's settings, seed and operator id the worker's own."""
    shard: Path
    """The store the worker creates and records into (its videos beside it)."""
    trials: int | None = None
    """Stop after this many trials; None: the mode decides."""
    skill: float = 1.0
    """The scripted expert's skill, in [0, 1]."""
    key_file: Path | None = None
    """Sign the shard's hash chain with the secret in this file."""
    cameras: CameraOptions | None = None
    """Cameras recorded as videos at the frame rate."""


def collect_shard(job: WorkerJob, on_trial: Callable[[TrialResult], None]) -> int:
    """Run ``job``'s session to its end, ``on_trial`` for each trial as it ends; returns
    the exit status (0; :data:`EXIT_STORAGE`; 130 or 143 when stopped by a signal)."""
    from workcell.control.simulation import Simulation  # noqa: PLC0415
    from workcell.expert import ExpertConfig, ExpertOperator  # noqa: PLC0415
    from workcell.record.chain import ChainKey  # noqa: PLC0415
    from workcell.recording.headless import make_recorder, run_recorded  # noqa: PLC0415
    from workcell.recording.in_process import InProcessStore  # noqa: PLC0415
    from workcell.recording.shutdown import ShutdownSignals, exit_status  # noqa: PLC0415
    from workcell.task.runner import SessionRunner  # noqa: PLC0415

    sim = Simulation(job.config.world)
    runner = SessionRunner(
        job.config, sim, ExpertOperator(ExpertConfig(skill=job.skill)), max_trials=job.trials
    )
    key = None if job.key_file is None else ChainKey.from_file(job.key_file)
    with InProcessStore.open(job.shard, writer=True, key=key) as store:
        recorder = make_recorder(store, job.shard, runner, job.cameras)
        shown = 0

        def after_step() -> None:
            nonlocal shown
            for result in runner.results[shown:]:
                on_trial(result)
            shown = len(runner.results)

        with ShutdownSignals() as shutdown:
            run_recorded(
                runner,
                recorder,
                lambda: None if shutdown.requested is None else "application_quit",
                after_step,
            )
    if recorder.failure is not None:
        print(f"workcell: error: {recorder.failure}", file=sys.stderr)
        return EXIT_STORAGE
    return 0 if shutdown.requested is None else exit_status(shutdown.requested)


def main() -> int:
    """The worker process: its job from standard input, its results to standard output
    (anything else printed goes to standard error)."""
    from workcell.recording.pipe_messages import receive, send  # noqa: PLC0415

    results = os.fdopen(os.dup(sys.stdout.fileno()), "wb")
    os.dup2(sys.stderr.fileno(), sys.stdout.fileno())
    job = receive(sys.stdin.buffer)
    try:
        return collect_shard(job, lambda result: send(results, result))
    except WorkcellError as error:
        print(f"workcell: error: {error}", file=sys.stderr)
        return EXIT_ERROR
    finally:
        results.close()


if __name__ == "__main__":
    sys.exit(main())

"""One scale-out worker: a whole session recorded into its own store shard.

A worker receives a :class:`WorkerJob` (frozen and picklable: the session configuration
already resolved, seed and trials the worker's own) and hands back each trial's
:class:`~workcell.task.runner.TrialResult` as it ends; it records, recovers and fails like
``workcell collect --writer inline`` (the same
:class:`~workcell.recording.recorded_session.RecordedSession`).
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
from workcell.expert.skill import ExpertConfig
from workcell.recording.drivers import Driver, ExpertDriver
from workcell.recording.media import CameraOptions
from workcell.recording.recorded_session import RecordedSessionConfig
from workcell.session.config import SessionConfig
from workcell.task.runner import TrialResult

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
    driver: Driver | None = None
    """Who drives (``workcell evaluate``: a policy); None: the expert at ``skill``."""

    def recorded_session(self) -> RecordedSessionConfig:
        """The session the worker runs: written in the worker's own process (the workers
        fill the cores already), as fast as possible."""
        return RecordedSessionConfig(
            session=self.config,
            driver=self.driver
            if self.driver is not None
            else ExpertDriver(ExpertConfig(self.skill)),
            store=self.shard,
            writer="inline",
            key_file=self.key_file,
            cameras=self.cameras,
            max_trials=self.trials,
        )


def collect_shard(job: WorkerJob, on_trial: Callable[[TrialResult], None]) -> int:
    """Run ``job``'s session to its end, ``on_trial`` for each trial as it ends; returns
    the exit status (0; :data:`~workcell.recording.headless.EXIT_STORAGE`; 130 or 143 when
    stopped by a signal)."""
    from workcell.recording.headless import headless_status, run_headless  # noqa: PLC0415
    from workcell.recording.recorded_session import RecordedSession  # noqa: PLC0415

    with RecordedSession.open(job.recorded_session()) as session:
        signal_name = run_headless(session, on_trial)
    return headless_status(session, signal_name)


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

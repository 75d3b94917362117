"""Attempts spread over long-lived worker processes that take them from one queue.

Each worker process is started once (a :class:`~concurrent.futures.ProcessPoolExecutor`),
receives the plan and the session settings once, and records every attempt it takes into a
store shard of its own; the attempts wait in the pool's queue, so a worker that finishes
early takes the next one. The shards are merged into the output store at the end
(:func:`~workcell.record.merge.merge_stores`, as ``workcell collect --workers`` does) and
verified. Workers ignore SIGINT: the caller stops handing out attempts, lets the running
ones finish and merges what was recorded.
"""

from __future__ import annotations

import os
import signal
from collections.abc import Callable, Sequence
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from pathlib import Path

from workcell.generate.attempts import AttemptResult, run_attempt
from workcell.generate.plan import GenerationPlan
from workcell.session.config import SessionConfig

_job: tuple[GenerationPlan, SessionConfig, Path] | None = None
"""The worker process's plan, settings and shard folder (set once, when it starts)."""


def _start_worker(plan: GenerationPlan, config: SessionConfig, shard_dir: Path) -> None:
    global _job  # noqa: PLW0603 - one job per worker process, set as it starts
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    _job = (plan, config, shard_dir)


def _attempt(attempt: int) -> AttemptResult | None:
    assert _job is not None, "a worker runs attempts only after it started"
    plan, config, shard_dir = _job
    return run_attempt(plan, config, attempt, shard_dir / f"shard-{os.getpid()}.sqlite")


def run_pool(
    plan: GenerationPlan,
    config: SessionConfig,
    attempts: Sequence[int],
    workers: int,
    shard_dir: Path,
    *,
    on_attempt: Callable[[AttemptResult], None],
    should_stop: Callable[[], bool],
) -> list[Path]:
    """Run ``attempts`` on ``workers`` processes, ``on_attempt`` for each as it ends;
    returns the shards written. Once ``should_stop`` says so, no further attempt starts."""
    with ProcessPoolExecutor(
        max_workers=workers, initializer=_start_worker, initargs=(plan, config, shard_dir)
    ) as pool:
        queue = list(attempts)
        running: set[Future[AttemptResult | None]] = set()
        while queue or running:
            while queue and len(running) < 2 * workers and not should_stop():
                running.add(pool.submit(_attempt, queue.pop(0)))
            if should_stop():
                queue.clear()
            if not running:
                break
            done, running = wait(running, timeout=0.5, return_when=FIRST_COMPLETED)
            for future in done:
                result = future.result()
                if result is not None:
                    on_attempt(result)
    return sorted(shard_dir.glob("shard-*.sqlite"))

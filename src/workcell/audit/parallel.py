"""Auditing a store's closed trials in several processes.

Each worker process opens the store read-only (its own snapshot: a closed trial never
changes, so every snapshot holds the same frames for it) and audits a share of the closed
trials; the results come back in trial order. Running trials are audited by the caller,
from its own snapshot.
"""

from __future__ import annotations

import multiprocessing
import os
from collections.abc import Iterator, Mapping, Sequence
from concurrent.futures import Future, ProcessPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path
from typing import TypeVar

from workcell.audit.auditor import TrialAuditor
from workcell.audit.config import AuditConfig
from workcell.audit.rows import SessionRow, TrialRow
from workcell.audit.source import Pauses
from workcell.audit.stage_pass import with_stages
from workcell.audit.store_source import StoreSource
from workcell.audit.trial_audit import TrialAudit
from workcell.record.entries import AnnotationRecord

MIN_FRAMES_PER_WORKER = 100_000
"""Below this many frames per worker, starting processes costs more than it saves."""
CHUNKS_PER_WORKER = 4
"""Shares per worker: progress is reported per share, and shares even out the load."""

T = TypeVar("T")


@dataclass(frozen=True)
class StoreJob:
    """What every worker needs to audit trials of one store."""

    path: Path
    use_blocks: bool
    sessions: tuple[SessionRow, ...]
    annotations: tuple[AnnotationRecord, ...]
    config: AuditConfig
    pauses: Mapping[str, Pauses] = field(default_factory=dict)
    """Each paused trial's pauses (the operator's; not sampling gaps)."""


def worker_count(requested: int | None, frames: int) -> int:
    """Workers to use: ``requested``, or (None) one per core while each gets at least
    :data:`MIN_FRAMES_PER_WORKER` frames."""
    if requested is not None:
        return max(1, requested)
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    return max(1, min(cores or 1, frames // MIN_FRAMES_PER_WORKER))


def shares(rows: Sequence[T], frames: Sequence[int], count: int) -> list[list[T]]:
    """``rows`` cut into up to ``count`` consecutive shares of about equal frames."""
    total = sum(frames) or 1
    out: list[list[T]] = [[]]
    done = 0
    for row, n in zip(rows, frames, strict=True):
        if out[-1] and done >= total * len(out) / count:
            out.append([])
        out[-1].append(row)
        done += n
    return [share for share in out if share]


def audit_in_workers(
    job: StoreJob, shares_: list[list[TrialRow]], workers: int
) -> Iterator[tuple[list[TrialRow], list[tuple[TrialAudit, int]]]]:
    """(share, [(audit, frames read)]) for each share, as they finish, in share order."""
    # fork: the workers start at once with the modules already imported
    method = "fork" if "fork" in multiprocessing.get_all_start_methods() else "spawn"
    context = multiprocessing.get_context(method)
    with ProcessPoolExecutor(workers, context, initializer=_start, initargs=(job,)) as pool:
        futures: list[Future[list[tuple[TrialAudit, int]]]] = [
            pool.submit(_audit_share, share) for share in shares_
        ]
        for share, future in zip(shares_, futures, strict=True):
            yield share, future.result()


_JOB: StoreJob | None = None


def _start(job: StoreJob) -> None:
    global _JOB  # noqa: PLW0603 (one job per worker process, set once when it starts)
    _JOB = job


def _audit_share(rows: list[TrialRow]) -> list[tuple[TrialAudit, int]]:
    job = _JOB
    assert job is not None
    auditor = TrialAuditor(job.sessions, job.annotations, job.config, job.pauses)
    by_id = {row.trial_id: row for row in rows}
    source = StoreSource(job.path, use_blocks=job.use_blocks)
    try:
        done = [
            (auditor.audit(by_id[trial_id], frames), len(frames))
            for trial_id, frames in source.frames_of(list(by_id))
        ]
        staged = with_stages(source, [audit for audit, _ in done])  # in the worker, too
        return [(audit, n) for audit, (_, n) in zip(staged, done, strict=True)]
    finally:
        source.close()

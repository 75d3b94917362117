"""Running an audit over a source: stream the trials, then select trajectories to draw."""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

from workcell.audit.auditor import TrialAuditor
from workcell.audit.config import AuditConfig
from workcell.audit.errors import AuditError
from workcell.audit.findings import SESSION, SOURCE, Finding, trial_findings
from workcell.audit.parallel import (
    CHUNKS_PER_WORKER,
    StoreJob,
    audit_in_workers,
    shares,
    worker_count,
)
from workcell.audit.population import flag_slow
from workcell.audit.rows import SessionRow
from workcell.audit.source import FRAME_COLUMNS_READ, AuditSource, FloatArray, Switches
from workcell.audit.stage_pass import with_stages
from workcell.audit.store_source import StoreSource
from workcell.audit.trial_audit import TrialAudit
from workcell.metrics import FrameArrays
from workcell.record.entries import AnnotationRecord

Progress = Callable[[int, int, int], None]
"""``progress(trials_done, trials_total, frames_read)``, called after each trial."""


@dataclass(frozen=True)
class AuditResult:
    """A finished audit: trials in session order (sessions by creation, trials by index),
    findings in that order, and the start-aligned floor-plane (x, y) TCP-midpoint paths of
    the temporally stratified successful trials the report draws."""

    config: AuditConfig
    source_kind: str
    source_path: str
    sessions: tuple[SessionRow, ...]
    trials: tuple[TrialAudit, ...]
    annotations: tuple[AnnotationRecord, ...]
    findings: tuple[Finding, ...]
    trajectories: dict[str, FloatArray]
    frames_read: int
    switches: Mapping[str, Switches] = field(default_factory=dict)
    """Each corrected trial's take-overs and hand-backs (:mod:`workcell.audit.interventions`)."""


def stratified(count: int, k: int) -> list[int]:
    """Up to ``k`` positions spread evenly over ``count`` ordered items, first and last
    included."""
    if count <= k:
        return list(range(count))
    return [int(i) for i in np.linspace(0, count - 1, k).round()]


def _start_aligned(xy: FloatArray) -> FloatArray:
    finite = np.flatnonzero(np.isfinite(xy).all(axis=1))
    return xy - xy[finite[0]] if len(finite) else xy


def run_audit(
    source: AuditSource,
    config: AuditConfig | None = None,
    progress: Progress | None = None,
    workers: int | None = 1,
) -> AuditResult:
    """Audit every trial of ``source``, reading one trial's frames at a time.

    A store's closed trials are audited by ``workers`` processes (None: one per core when
    there are enough frames to gain from it, see :mod:`workcell.audit.parallel`)."""
    config = config or AuditConfig()
    annotations = tuple(source.annotations())
    rows = {row.trial_id: row for row in source.trials()}
    pauses = source.trial_pauses(list(rows))
    auditor = TrialAuditor(source.sessions(), annotations, config, pauses)
    for trial_row in rows.values():
        if trial_row.session_id not in auditor.sessions:
            raise AuditError(
                f"{source.path}: trial {trial_row.trial_id} names session "
                f"{trial_row.session_id}, which the source does not hold"
            )
    findings: list[Finding] = []
    done: dict[str, TrialAudit] = {}
    frames_read = 0

    def tick() -> None:
        if progress is not None:
            progress(len(done), len(rows), frames_read)

    pairs = source.frames()
    if isinstance(source, StoreSource):
        closed = [row for row in rows.values() if row.outcome is not None]
        sizes = [int(row.stored.get("n_frames") or 0) for row in closed]
        count = worker_count(workers, sum(sizes))
        if count > 1:
            job = StoreJob(
                source.path,
                source.use_blocks,
                tuple(auditor.sessions.values()),
                annotations,
                config,
                pauses,
            )
            for _, results in audit_in_workers(
                job, shares(closed, sizes, count * CHUNKS_PER_WORKER), count
            ):
                for audit, n in results:
                    done[audit.trial_id] = audit
                    frames_read += n
                tick()
            pairs = source.frames_of([t for t in rows if t not in done])  # running trials
    for trial_id, frames in pairs:
        row = rows.get(trial_id)
        if row is None:
            message = f"{len(frames)} frames of trial {trial_id}, which no trial row holds"
            findings.append(Finding(SOURCE, "orphan_frames", message, trial_id))
            continue
        done[trial_id] = auditor.audit(row, frames)
        frames_read += len(frames)
        tick()
    empty = FrameArrays.from_matrix(np.empty((0, len(FRAME_COLUMNS_READ))))
    for trial_id, row in rows.items():
        if trial_id not in done:
            done[trial_id] = auditor.audit(row, empty)
    sessions = sorted(auditor.sessions.values(), key=lambda s: (s.created_wall, s.session_id))
    position = {s.session_id: i for i, s in enumerate(sessions)}
    trials = sorted(done.values(), key=lambda t: (position[t.row.session_id], t.row.trial_index))
    switches = source.trial_switches(list(rows))
    taken_over = {t for t, kinds in switches.items() if any(k == "take_over" for k, _ in kinds)}
    trials = flag_slow(trials, config.slowness, taken_over)  # the whole set: after every trial
    trials = with_stages(source, trials)  # those the workers did not read
    for session in sessions:
        for text in session.notes:
            findings.append(Finding(SESSION, "defaults", text, session_id=session.session_id))
    for trial in trials:
        findings += trial_findings(trial)
    for note in annotations:
        if note.trial_id not in rows:
            message = f"annotation {note.annotation_id} names trial {note.trial_id}, not found"
            findings.append(Finding(SOURCE, "orphan_annotation", message, note.trial_id))
    return AuditResult(
        config=config,
        source_kind=source.kind,
        source_path=str(source.path),
        sessions=tuple(sessions),
        trials=tuple(trials),
        annotations=annotations,
        findings=tuple(findings),
        trajectories=_trajectories(source, trials, config.trajectories),
        frames_read=frames_read,
        switches=switches,
    )


def _trajectories(
    source: AuditSource, trials: Sequence[TrialAudit], k: int
) -> dict[str, FloatArray]:
    successes = [t.trial_id for t in trials if t.valid_success]
    chosen = [successes[i] for i in stratified(len(successes), k)]
    paths = source.midpoints(chosen)
    return {trial_id: _start_aligned(paths[trial_id]) for trial_id in chosen if trial_id in paths}

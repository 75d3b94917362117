"""One trial audited: metrics recomputed from its frames, flags, cross-check, disposition."""

from __future__ import annotations

from dataclasses import dataclass

from workcell.audit.config import AuditConfig
from workcell.audit.crosscheck import Mismatch, crosscheck
from workcell.audit.disposition import Disposition, decide
from workcell.audit.flags import Flag
from workcell.audit.nonfinite import detect_nonfinite
from workcell.audit.oscillation import OscillationCriteria, detect_oscillation
from workcell.audit.rows import SessionRow, TrialRow
from workcell.audit.sampling import detect_sampling
from workcell.audit.source import Pauses
from workcell.audit.task_stages import TaskStage
from workcell.metrics import FrameArrays, TrialMetrics, compute_trial_metrics
from workcell.record.entries import AnnotationRecord


@dataclass(frozen=True)
class TrialAudit:
    """Everything the audit concluded about one trial. ``metrics`` are recomputed from the
    frames; ``row`` holds what was stored, untouched."""

    row: TrialRow
    session: SessionRow
    metrics: TrialMetrics
    flags: tuple[Flag, ...]
    mismatches: tuple[Mismatch, ...]
    disposition: Disposition
    task_stage: str | None = None
    """How far the trial got, one of its task's stages (:mod:`workcell.audit.stage_pass`):
    as recorded, or for a box-transfer trial recorded before stages were read from the
    frames; None until read (after every trial is audited) or where nothing says."""
    recomputed_stage: TaskStage | None = None
    """For a box-transfer trial whose stage was recorded: the stage its frames say (the
    cross-check), where they were read."""

    @property
    def trial_id(self) -> str:
        return self.row.trial_id

    @property
    def task(self) -> str:
        """The trial's task (``task.kind``): as its row records it, else its session's."""
        return self.row.task or self.session.task

    @property
    def valid_success(self) -> bool:
        return self.disposition.included and self.row.outcome == "success"


def detect_flags(
    frames: FrameArrays,
    metrics: TrialMetrics,
    session: SessionRow,
    config: AuditConfig,
    criteria: OscillationCriteria | None,
    *,
    pauses: Pauses = (),
) -> tuple[Flag, ...]:
    """Every quality flag of one trial, in FLAG_NAMES order (``pauses``: the operator's,
    not sampling gaps)."""
    flags: list[Flag] = []
    if criteria is not None:
        grip = session.thresholds.grip_threshold
        oscillation = detect_oscillation(
            frames,
            frames.grip_l >= grip,
            frames.grip_r >= grip,
            criteria,
            config.oscillation.disqualifying,
        )
        if oscillation is not None:
            flags.append(oscillation)
    flags += detect_sampling(frames, session.rate_hz, config.sampling, pauses)
    nonfinite = detect_nonfinite(metrics, config.nonfinite)
    if nonfinite is not None:
        flags.append(nonfinite)
    return tuple(flags)


def audit_trial(
    row: TrialRow,
    session: SessionRow,
    frames: FrameArrays,
    *,
    review: AnnotationRecord | None,
    config: AuditConfig,
    criteria: OscillationCriteria | None,
    pauses: Pauses = (),
) -> TrialAudit:
    """Audit one trial; ``criteria`` are the oscillation criteria at the session's rate
    (None when that rate cannot resolve them)."""
    metrics = compute_trial_metrics(frames, row.outcome == "success", session.thresholds)
    flags = detect_flags(frames, metrics, session, config, criteria, pauses=pauses)
    return TrialAudit(
        row=row,
        session=session,
        metrics=metrics,
        flags=flags,
        mismatches=crosscheck(row, metrics, config.tolerance),
        disposition=decide(row, flags, review),
    )

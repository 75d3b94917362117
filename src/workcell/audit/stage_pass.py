"""The task-stage pass: how far each audited trial got, read from its source after the
trial's audit (:mod:`workcell.audit.task_stages` holds the definitions)."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace

from workcell.audit.source import AuditSource
from workcell.audit.task_stages import NO_STAGE_FRAMES, stage_reached, trial_zone
from workcell.audit.trial_audit import TrialAudit


def with_stages(source: AuditSource, trials: Sequence[TrialAudit]) -> list[TrialAudit]:
    """``trials`` with the stage each reached, where not read already. A trial that
    delivered a box is ``delivered`` by definition; only the others are read from their
    frames."""
    unread = [t.trial_id for t in trials if t.task_stage is None and not delivered(t)]
    frames = source.stage_frames(unread) if unread else {}
    conditions = source.trial_conditions(unread) if unread else {}
    return [
        trial
        if trial.task_stage is not None
        else replace(
            trial,
            task_stage=stage_reached(
                frames.get(trial.trial_id, NO_STAGE_FRAMES),
                trial_zone(trial.session.zone, conditions.get(trial.trial_id)),
                trial.row.stored.get("boxes_delivered"),
            ),
        )
        for trial in trials
    ]


def delivered(trial: TrialAudit) -> bool:
    """Whether the trial's row says it delivered at least one box."""
    count = trial.row.stored.get("boxes_delivered")
    return count is not None and count >= 1

"""The task-stage pass: how far each audited trial got, among its own task's stages.

A trial recorded since schema version 5 holds the furthest stage its task's judge said it
reached (the ``stage`` column): that is its stage. A box-transfer trial recorded before
has its stage read from its frames (:mod:`workcell.audit.task_stages`, box transfer's
definitions); a trial of another task recorded before says none. For a box-transfer trial
with a recorded stage, the frames are read too, as a cross-check (only where cheap: a
trial that finished a box is at the last stage by definition, so only the others' frames
are read); a disagreement is a finding (:mod:`workcell.audit.findings`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace

from workcell.audit.source import AuditSource
from workcell.audit.task_stages import (
    FRAMES_TASK,
    NO_STAGE_FRAMES,
    TaskStage,
    stage_reached,
    trial_zone,
)
from workcell.audit.trial_audit import TrialAudit
from workcell.tasks.box_transfer.stages import COMPLETED_COLUMN

FRAMES_DEFINE = FRAMES_TASK
"""The task whose stages the frames define (:mod:`workcell.audit.task_stages`)."""


def with_stages(source: AuditSource, trials: Sequence[TrialAudit]) -> list[TrialAudit]:
    """``trials`` with the stage each reached (and, for box transfer, the stage its frames
    say), where not read already."""
    unread = [
        t.trial_id
        for t in trials
        if t.task == FRAMES_DEFINE
        and not finished(t)
        and (t.task_stage is None or t.row.recorded_stage is not None)
        and t.recomputed_stage is None
    ]
    frames = source.stage_frames(unread) if unread else {}
    conditions = source.trial_conditions(unread) if unread else {}

    def from_frames(trial: TrialAudit) -> TaskStage:
        return stage_reached(
            frames.get(trial.trial_id, NO_STAGE_FRAMES),
            trial_zone(trial.session.zone, conditions.get(trial.trial_id)),
            trial.row.stored.get(COMPLETED_COLUMN),
        )

    out: list[TrialAudit] = []
    for trial in trials:
        recomputed = trial.recomputed_stage
        if trial.task == FRAMES_DEFINE and recomputed is None:
            recomputed = from_frames(trial)  # finished: without reading frames
        stage = trial.task_stage or trial.row.recorded_stage
        if stage is None and trial.task == FRAMES_DEFINE:
            stage = recomputed
        out.append(replace(trial, task_stage=stage, recomputed_stage=recomputed))
    return out


def stage_disagrees(trial: TrialAudit) -> bool:
    """Whether a box-transfer trial's recorded stage is not the stage its frames say."""
    recorded = trial.row.recorded_stage
    return (
        trial.task == FRAMES_DEFINE
        and recorded is not None
        and trial.recomputed_stage is not None
        and recorded != trial.recomputed_stage
    )


def finished(trial: TrialAudit) -> bool:
    """Whether the trial's row says it finished at least one box (box transfer's
    :data:`~workcell.tasks.box_transfer.stages.COMPLETED_COLUMN`)."""
    count = trial.row.stored.get(COMPLETED_COLUMN)
    return count is not None and count >= 1

"""What the replay page shows beside the 3D view: the trial's facts (who ran it, in which
condition and study step, how it ended, included or not: as the Sessions page and the
exports say it) and its event timeline."""

from __future__ import annotations

from typing import Any

from workcell.protocol.api import ReplayFacts, TimelineEvent
from workcell.record.entries import EventRecord, SessionRecord, TrialRecord
from workcell.record.inclusion import decide
from workcell.record.store import Store
from workcell.record.study_tags import StudyTags

LEFT_OFF_TIMELINE = frozenset({"client_frames", "media"})
"""Event kinds the timeline leaves out: the page's frame-time reports and the recorded
videos' bookkeeping say nothing of what happened in the trial."""
DETAIL_CHARACTERS = 80
QUIET_KEYS = frozenset({"t_sim", "trial_index", "kind"})
"""Payload keys every event repeats (its time and trial): not part of its detail."""


def replay_facts(store: Store, session: SessionRecord, trial: TrialRecord) -> ReplayFacts:
    tags = StudyTags.of(session.operator_id, session.parameters)
    included: bool | None = None
    reason: str | None = None
    if trial.outcome is not None:
        inclusion = decide(trial, store.annotations(trial.trial_id))
        included, reason = inclusion.included, inclusion.reason
    return ReplayFacts(
        operator_id=tags.operator_id,
        condition=tags.condition,
        study_step=tags.study_step,
        mode=trial.mode,
        round=trial.round,
        level=trial.level,
        required_boxes=trial.required_boxes,
        time_limit_s=trial.time_limit_s,
        outcome=trial.outcome,
        interruption_reason=trial.interruption_reason,
        elapsed_s=trial.elapsed_s,
        boxes_delivered=trial.boxes_delivered,
        score=trial.score,
        included=included,
        exclusion_reason=reason,
    )


def timeline(events: list[EventRecord]) -> tuple[TimelineEvent, ...]:
    """The trial's events on its clock, in time order (recording order among equals)."""
    marks = [
        TimelineEvent(t=round(e.t_sim, 6), kind=e.kind, detail=event_detail(e.payload))
        for e in sorted(events, key=lambda e: e.seq)
        if e.t_sim is not None and e.kind not in LEFT_OFF_TIMELINE
    ]
    return tuple(sorted(marks, key=lambda mark: mark.t))


def event_detail(payload: dict[str, Any]) -> str:
    """``box=0 side=l`` from a payload: its own keys and short values, cut to a line."""
    parts = [
        f"{key}={_short(value)}"
        for key, value in payload.items()
        if key not in QUIET_KEYS and value is not None
    ]
    text = " ".join(parts)
    return text if len(text) <= DETAIL_CHARACTERS else text[: DETAIL_CHARACTERS - 1] + "…"


def _short(value: Any) -> str:
    if isinstance(value, float):
        return f"{value:.3g}"
    if isinstance(value, list | tuple | dict):
        return "…"
    return str(value)

"""Which trials become episodes, whether each counts as included, and what was left out.

A trial's inclusion is :func:`workcell.record.inclusion.decide`'s, the one the Sessions page
shows: incomplete (interrupted) trials are never included, a reviewer's latest decision
wins, else the store's ``included`` column. With :attr:`TrialFilter.audited` the audit
decides instead (:mod:`workcell.export.audited`). Running trials (no outcome yet) and
trials without frames are never exported. :attr:`Selection.left_out` counts every closed
trial left out, per reason, so an export says what it left out and why.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Mapping
from dataclasses import dataclass, field

from workcell.export.options import TrialFilter
from workcell.record.entries import AnnotationRecord, SessionRecord, TrialRecord
from workcell.record.inclusion import Inclusion, decide, left_out_as
from workcell.record.store import Store
from workcell.tasks.registry import recorded_kind

__all__ = ["EpisodeSource", "Inclusion", "Selection", "decide", "select"]

WITHOUT_FRAMES = "without frames"
NOT_SUCCESSFUL = "not successful (--successes)"
OTHER_TASK = "another task (--task)"
OTHER_OPERATOR = "another operator (--operator)"


@dataclass(frozen=True)
class EpisodeSource:
    """A closed trial with frames, its session and its inclusion."""

    session: SessionRecord
    trial: TrialRecord
    inclusion: Inclusion


@dataclass(frozen=True)
class Selection:
    """The episodes to export, in recording order, and what was left out."""

    episodes: tuple[EpisodeSource, ...]
    closed: int
    """Closed trials in the store (with or without frames)."""
    excluded: int
    """Closed trials with frames left out because they are not included."""
    without_frames: int
    not_successes: int = 0
    """Included trials left out because they did not succeed (``successes_only``)."""
    left_out: dict[str, int] = field(default_factory=dict)
    """Every closed trial left out, counted per reason (most first): its exclusion reason
    (:mod:`workcell.record.inclusion`), ``without frames`` or ``not successful``."""


def select(
    store: Store,
    rule: TrialFilter,
    audited: Mapping[str, Inclusion] | None = None,
) -> Selection:
    """Closed trials with frames, in recording order, chosen by ``rule``; ``audited``
    holds the audit's decisions when ``rule.audited``."""
    sessions = {s.session_id: s for s in store.sessions()}
    order = {session_id: i for i, session_id in enumerate(sessions)}
    trials = sorted(
        (t for t in store.trials() if t.outcome is not None),
        key=lambda t: (order[t.session_id], t.trial_index),
    )
    annotations: dict[str, list[AnnotationRecord]] = {}
    for annotation in store.annotations():
        annotations.setdefault(annotation.trial_id, []).append(annotation)
    chosen: list[EpisodeSource] = []
    left_out: Counter[str] = Counter()
    excluded = without_frames = not_successes = 0
    for trial in trials:
        session = sessions[trial.session_id]
        if rule.tasks and recorded_kind(session.parameters) not in rule.tasks:
            left_out[OTHER_TASK] += 1
            continue
        if rule.operators and session.operator_id not in rule.operators:
            left_out[OTHER_OPERATOR] += 1
            continue
        if not trial.n_frames:
            without_frames += 1
            left_out[WITHOUT_FRAMES] += 1
            continue
        if rule.audited and audited is not None:
            inclusion = audited[trial.trial_id]
        else:
            inclusion = decide(trial, annotations.get(trial.trial_id, []))
        if not (inclusion.included or rule.include_all):
            excluded += 1
            left_out[left_out_as(inclusion.reason or "not included")] += 1
            continue
        if rule.successes_only and trial.outcome != "success":
            not_successes += 1
            left_out[NOT_SUCCESSFUL] += 1
            continue
        chosen.append(EpisodeSource(session, trial, inclusion))
    return Selection(
        tuple(chosen),
        len(trials),
        excluded,
        without_frames,
        not_successes,
        dict(left_out.most_common()),
    )

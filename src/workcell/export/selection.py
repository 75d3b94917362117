"""Which trials become episodes, and whether each counts as included.

A trial's inclusion is the store's ``included`` column unless a reviewer decided
otherwise: the latest ``include``/``exclude`` annotation wins (annotations never rewrite
the trial row). An interrupted trial is never included. With :attr:`TrialFilter.audited`
the audit decides instead (:mod:`workcell.export.audited`). Running trials (no outcome
yet) and trials without frames are never exported.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

from workcell.export.options import TrialFilter
from workcell.record.entries import AnnotationRecord, SessionRecord, TrialRecord
from workcell.record.store import Store

DECISION_KINDS = ("include", "exclude")


@dataclass(frozen=True)
class Inclusion:
    """The effective decision on one trial and where it came from."""

    included: bool
    reason: str | None
    """Why it is excluded (None when included)."""
    review: AnnotationRecord | None
    """The reviewer's annotation that decided it, if any."""


@dataclass(frozen=True)
class EpisodeSource:
    """A closed trial with frames, its session and its inclusion."""

    session: SessionRecord
    trial: TrialRecord
    inclusion: Inclusion


def decide(trial: TrialRecord, annotations: Sequence[AnnotationRecord]) -> Inclusion:
    """The effective inclusion of a closed trial (``annotations`` in time order)."""
    if trial.outcome == "interrupted":
        return Inclusion(False, f"interrupted ({trial.interruption_reason})", None)
    decisions = [a for a in annotations if a.kind in DECISION_KINDS]
    if decisions:
        latest = decisions[-1]
        included = latest.kind == "include"
        return Inclusion(included, None if included else latest.reason, latest)
    included = bool(trial.included)
    reason = None if included else (trial.exclusion_reason or "not included")
    return Inclusion(included, reason, None)


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
    excluded = without_frames = not_successes = 0
    for trial in trials:
        if not trial.n_frames:
            without_frames += 1
            continue
        if rule.audited and audited is not None:
            inclusion = audited[trial.trial_id]
        else:
            inclusion = decide(trial, annotations.get(trial.trial_id, []))
        if not (inclusion.included or rule.include_all):
            excluded += 1
            continue
        if rule.successes_only and trial.outcome != "success":
            not_successes += 1
            continue
        chosen.append(EpisodeSource(sessions[trial.session_id], trial, inclusion))
    return Selection(tuple(chosen), len(trials), excluded, without_frames, not_successes)

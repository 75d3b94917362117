"""One vocabulary for whether a trial is included, from the store to the pages to the
exports (paper: outcome, inclusion and quality flags are independent).

- A trial without a complete outcome is **incomplete** and never included: the store
  writes an interrupted trial ``included = 0`` with the exclusion reason
  ``incomplete: interrupted (<interruption reason>)``, as the audit words it.
- A reviewer's latest ``include``/``exclude`` annotation decides a complete trial
  (annotations never rewrite the trial row): excluded, its reason reads
  ``excluded by reviewer <who>: <why>``.
- Otherwise the trial row's own ``included`` column decides.

:func:`decide` is that rule: the Sessions page (``/api/sessions``) and the dataset exports'
default selection both show it; ``workcell audit`` adds its quality rules on top and
``export --audited`` takes the audit's decision. Every exclusion reason begins with why,
so that what an export leaves out can be counted per reason (:func:`left_out_as`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from workcell.record.columns import COMPLETE_OUTCOMES
from workcell.record.entries import AnnotationRecord, TrialRecord

DECISION_KINDS = ("include", "exclude")
"""Annotation kinds that decide; a ``note`` only comments."""
INCOMPLETE = "incomplete"
EXCLUDED_BY_REVIEWER = "excluded by reviewer"
NOT_INCLUDED = "not included"
"""The reason of a complete trial the store holds not included without saying why."""


def incomplete_reason(outcome: str | None, interruption_reason: str | None) -> str:
    """``incomplete: interrupted (operator_stop)``; a trial never closed is
    ``incomplete: no outcome (never_closed)``."""
    return f"{INCOMPLETE}: {outcome or 'no outcome'} ({interruption_reason or 'never_closed'})"


def reviewer_reason(by: str, reason: str) -> str:
    return f"{EXCLUDED_BY_REVIEWER} {by}: {reason}"


def left_out_as(reason: str) -> str:
    """The reason an excluded trial is counted under: its reason, but a reviewer's
    exclusion counted as ``excluded by reviewer`` (whatever each reviewer wrote)."""
    return EXCLUDED_BY_REVIEWER if reason.startswith(EXCLUDED_BY_REVIEWER) else reason


@dataclass(frozen=True)
class Inclusion:
    """The effective decision on one trial and where it came from."""

    included: bool
    reason: str | None
    """Why it is excluded (None when included)."""
    review: AnnotationRecord | None
    """The reviewer's annotation that decided it, if any."""


def decide(trial: TrialRecord, annotations: Sequence[AnnotationRecord]) -> Inclusion:
    """The effective inclusion of a trial (``annotations``: its own, in time order)."""
    if trial.outcome not in COMPLETE_OUTCOMES:
        return Inclusion(False, incomplete_reason(trial.outcome, trial.interruption_reason), None)
    decisions = [a for a in annotations if a.kind in DECISION_KINDS]
    if decisions:
        latest = decisions[-1]
        if latest.kind == "include":
            return Inclusion(True, None, latest)
        return Inclusion(False, reviewer_reason(latest.by, latest.reason), latest)
    included = bool(trial.included)
    reason = None if included else (trial.exclusion_reason or NOT_INCLUDED)
    return Inclusion(included, reason, None)

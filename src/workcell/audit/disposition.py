"""Dispositions (paper Fig. 4): which trials are valid, and why the others are not.

Automatic rules, in order:
1. a trial without a complete outcome (``interrupted``, or never closed) is excluded as
   incomplete;
2. a success with a disqualifying quality flag is excluded as low quality;
3. every other success and every timeout or failure (a trial its task's judge said could
   no longer succeed) is valid; a valid trial with any flag is *marked* (a flagged
   timeout or failure is kept as a genuine failure, paper §IV-B).

A reviewer's latest ``include`` or ``exclude`` annotation of a trial overrides rules 2 and
3 and is shown as the reviewer's decision. Exclusion reasons are worded as everywhere else
(:mod:`workcell.record.inclusion`: ``incomplete: interrupted (operator_stop)``,
``excluded by reviewer <who>: <why>``; the audit adds ``low quality: <flags>``). An
incomplete trial cannot be included: it has no outcome to count. Annotations are rows of
their own; stored trials are never changed.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass, replace

from workcell.audit.flags import Flag
from workcell.audit.rows import TrialRow
from workcell.record.columns import COMPLETE_OUTCOMES
from workcell.record.entries import AnnotationRecord
from workcell.record.inclusion import incomplete_reason, reviewer_reason

EXCLUDED_INCOMPLETE = "excluded_incomplete"
EXCLUDED_LOW_QUALITY = "excluded_low_quality"
EXCLUDED_BY_REVIEWER = "excluded_by_reviewer"
VALID_SUCCESS = "valid_success"
VALID_TIMEOUT = "valid_timeout"
VALID_FAILED = "valid_failed"
STAGES: tuple[str, ...] = (
    EXCLUDED_INCOMPLETE,
    EXCLUDED_LOW_QUALITY,
    EXCLUDED_BY_REVIEWER,
    VALID_SUCCESS,
    VALID_TIMEOUT,
    VALID_FAILED,
)
VALID_STAGES: dict[str, str] = {
    "success": VALID_SUCCESS,
    "timeout": VALID_TIMEOUT,
    "failed": VALID_FAILED,
}
"""The stage of a valid trial, by its outcome (every complete outcome)."""
"""Every final disposition of a trial."""

DECISIONS = ("include", "exclude")
"""Annotation kinds that decide; a ``note`` only comments."""


@dataclass(frozen=True)
class Disposition:
    """A trial's final place in Fig. 4 and how it got there.

    ``cause`` is the short reason shown in the flow figure (an interruption reason, flag
    names, or ``reviewer``); ``review`` the deciding annotation, if any; ``overridden``
    whether it changed the automatic decision; ``refused`` why it could not apply.
    """

    stage: str
    included: bool
    exclusion_reason: str | None
    cause: str | None
    automatic_included: bool
    automatic_reason: str | None
    marked: bool
    review: AnnotationRecord | None = None
    overridden: bool = False
    refused: str | None = None


def latest_decisions(annotations: Iterable[AnnotationRecord]) -> dict[str, AnnotationRecord]:
    """Each trial's latest include/exclude annotation (by time, then given order)."""
    latest: dict[str, AnnotationRecord] = {}
    for note in sorted(annotations, key=lambda a: a.at_wall):
        if note.kind in DECISIONS:
            latest[note.trial_id] = note
    return latest


def _automatic(row: TrialRow, flags: Sequence[Flag]) -> tuple[str, str | None, str | None]:
    """(stage, exclusion reason, cause) by rules 1-3."""
    if row.outcome not in COMPLETE_OUTCOMES:
        cause = row.interruption_reason or "never_closed"
        return EXCLUDED_INCOMPLETE, incomplete_reason(row.outcome, row.interruption_reason), cause
    if row.outcome == "success":
        bad = sorted({f.name for f in flags if f.disqualifying})
        if bad:
            cause = ", ".join(bad)
            return EXCLUDED_LOW_QUALITY, f"low quality: {cause}", cause
        return VALID_SUCCESS, None, None
    return VALID_STAGES[row.outcome], None, None


def decide(row: TrialRow, flags: Sequence[Flag], review: AnnotationRecord | None) -> Disposition:
    """The disposition of one trial given its flags and its latest reviewer decision."""
    stage, reason, cause = _automatic(row, flags)
    valid = stage in VALID_STAGES.values()
    auto = Disposition(
        stage=stage,
        included=valid,
        exclusion_reason=reason,
        cause=cause,
        automatic_included=valid,
        automatic_reason=reason,
        marked=valid and bool(flags),
    )
    if review is None:
        return auto
    if review.kind == "include" and stage == EXCLUDED_INCOMPLETE:
        what = row.outcome or "open"
        refused = f"include by {review.by} not applied: an {what} trial has no outcome"
        return replace(auto, review=review, refused=refused)
    if (review.kind == "include") == valid:  # the reviewer agrees with the rules
        return replace(auto, review=review)
    if review.kind == "exclude":
        return replace(
            auto,
            stage=EXCLUDED_BY_REVIEWER,
            included=False,
            exclusion_reason=reviewer_reason(review.by, review.reason),
            cause="reviewer",
            marked=False,
            review=review,
            overridden=True,
        )
    return replace(
        auto,
        stage=VALID_STAGES[row.outcome or "timeout"],
        included=True,
        exclusion_reason=None,
        cause="reviewer",
        marked=bool(flags),
        review=review,
        overridden=True,
    )

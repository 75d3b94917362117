"""How many trials reach each stage of the disposition flow (paper Fig. 4), and why the
others left it."""

from __future__ import annotations

from collections import Counter
from collections.abc import Sequence
from dataclasses import dataclass

from workcell.audit.disposition import (
    EXCLUDED_BY_REVIEWER,
    EXCLUDED_INCOMPLETE,
    EXCLUDED_LOW_QUALITY,
    VALID_FAILED,
    VALID_SUCCESS,
    VALID_TIMEOUT,
)
from workcell.audit.trial_audit import TrialAudit


@dataclass(frozen=True)
class DispositionCounts:
    """raw -> incomplete | complete (successes + timeouts) -> low quality | reviewer
    excluded -> valid (successes + timeouts). ``*_causes`` count the short reasons;
    ``marked_*`` count valid trials kept despite a flag; ``included_by_reviewer`` valid
    trials the automatic rules had excluded. ``*_failures`` count the trials whose task's
    judge said they could no longer succeed (outcome ``failed``), kept apart from the
    timeouts (added after the paper's Fig. 4, which knows only timeouts)."""

    raw: int
    incomplete: int
    incomplete_causes: dict[str, int]
    complete: int
    complete_successes: int
    complete_timeouts: int
    excluded_low_quality: int
    low_quality_causes: dict[str, int]
    excluded_by_reviewer: int
    included_by_reviewer: int
    valid: int
    valid_successes: int
    valid_timeouts: int
    marked_successes: int
    marked_timeouts: int
    complete_failures: int = 0
    valid_failures: int = 0
    marked_failures: int = 0

    @classmethod
    def of(cls, trials: Sequence[TrialAudit]) -> DispositionCounts:
        stage = Counter(t.disposition.stage for t in trials)
        complete = [t for t in trials if t.disposition.stage != EXCLUDED_INCOMPLETE]
        incomplete_causes = Counter(
            t.disposition.cause or "" for t in trials if t.disposition.stage == EXCLUDED_INCOMPLETE
        )
        low_quality_causes = Counter(
            t.disposition.cause or "" for t in trials if t.disposition.stage == EXCLUDED_LOW_QUALITY
        )
        valid = [t for t in trials if t.disposition.included]
        return cls(
            raw=len(trials),
            incomplete=stage[EXCLUDED_INCOMPLETE],
            incomplete_causes=dict(sorted(incomplete_causes.items())),
            complete=len(complete),
            complete_successes=sum(t.row.outcome == "success" for t in complete),
            complete_timeouts=sum(t.row.outcome == "timeout" for t in complete),
            excluded_low_quality=stage[EXCLUDED_LOW_QUALITY],
            low_quality_causes=dict(sorted(low_quality_causes.items())),
            excluded_by_reviewer=stage[EXCLUDED_BY_REVIEWER],
            included_by_reviewer=sum(t.disposition.overridden for t in valid),
            valid=len(valid),
            valid_successes=stage[VALID_SUCCESS],
            valid_timeouts=stage[VALID_TIMEOUT],
            marked_successes=sum(t.disposition.marked for t in valid if t.row.outcome == "success"),
            marked_timeouts=sum(t.disposition.marked for t in valid if t.row.outcome == "timeout"),
            complete_failures=sum(t.row.outcome == "failed" for t in complete),
            valid_failures=stage[VALID_FAILED],
            marked_failures=sum(t.disposition.marked for t in valid if t.row.outcome == "failed"),
        )


def counted(n: int, noun: str, plural: str | None = None) -> str:
    """``n`` and ``noun``, plural unless ``n`` is 1: '1 trial', '2 trials', '0 successes'."""
    return f"{n} {noun if n == 1 else plural or noun + 's'}"

"""Conditions compared within participants (``workcell audit --by condition`` on a
within-subject study, where every participant runs every condition).

The design: within-subject when the audit is given the study file (a study's participants
run every condition) or, without one, when a participant's trials span more than one
condition; between-subject otherwise, compared by the pooled tests of
:mod:`workcell.audit.comparison`.

Per participant and condition (a cell), over their trials in that condition that are not
practice: trials, valid trials, valid successes, the success rate of the valid trials and
the median completion time and TCP path of the valid successes. Between every two
conditions, and between the condition each participant ran first and the one they ran
second (the order effect: position in their own sequence, read from the order their
sessions ran), the paired test of :mod:`workcell.audit.wilcoxon` on each participant's
success rate, median completion time and median path, with the matched-pairs
rank-biserial correlation and its bootstrap interval over participants. A participant
without a value in both (no valid trial, or no valid success for a time) is left out of
that test. Trials without a condition, practice trials and (given the study) trials of
operators who are not its participants are left out, and counted.
"""

from __future__ import annotations

import math
import statistics
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Literal

from workcell.audit.stats import metric_values
from workcell.audit.study_progress import StudyProgress
from workcell.audit.trial_audit import TrialAudit
from workcell.audit.wilcoxon import PairedParams, PairedTest, paired_test

Design = Literal["within", "between"]
PRACTICE = "practice"

PAIRED_METRICS: dict[str, tuple[str, str, float]] = {
    "success_rate": ("success rate", "points", 100.0),
    "completion_time_s": ("completion time", "s", 1.0),
    "path_length_m": ("TCP path", "m", 1.0),
}
"""Each participant's value compared in pairs: name, unit as shown, and the factor from
the stored value to the unit (a rate is a share 0-1, shown in percentage points)."""


@dataclass(frozen=True)
class Cell:
    """One participant's trials in one condition (practice left out)."""

    participant: str
    condition: str
    trials: int
    valid: int
    successes: int
    """Valid successes."""
    values: dict[str, float]
    """Per :data:`PAIRED_METRICS`: the success rate (share 0-1) of the valid trials, the
    median completion time and path of the valid successes (NaN: none)."""


@dataclass(frozen=True)
class PairedComparison:
    """``first`` against ``second`` (two conditions, or the positions ``first`` and
    ``second`` of the order effect), one test per metric of :data:`PAIRED_METRICS`."""

    first: str
    second: str
    tests: dict[str, PairedTest]


@dataclass(frozen=True)
class WithinSubject:
    design_reason: str
    participants: tuple[str, ...]
    conditions: tuple[str, ...]
    cells: dict[tuple[str, str], Cell]
    """By (participant, condition); a pair without trials has no cell."""
    orders: dict[str, tuple[str, ...]]
    """Per participant, the conditions in the order they ran them."""
    pairs: tuple[PairedComparison, ...]
    order_effect: PairedComparison
    left_out: dict[str, int]
    """Trials left out of the cells, by reason."""
    params: PairedParams
    study: StudyProgress | None


def _median(values: Sequence[float]) -> float:
    finite = [v for v in values if math.isfinite(v)]
    return float(statistics.median(finite)) if finite else math.nan


def cell_of(participant: str, condition: str, trials: Sequence[TrialAudit]) -> Cell:
    valid = [t for t in trials if t.disposition.included]
    successes = [t for t in valid if t.row.outcome == "success"]
    return Cell(
        participant,
        condition,
        trials=len(trials),
        valid=len(valid),
        successes=len(successes),
        values={
            "success_rate": len(successes) / len(valid) if valid else math.nan,
            "completion_time_s": _median(metric_values(successes, "completion_time_s")),
            "path_length_m": _median(metric_values(successes, "path_length_m")),
        },
    )


def design_of(trials: Sequence[TrialAudit], study: StudyProgress | None) -> tuple[Design, str]:
    """The design and why: the study's, or what the trials show."""
    if study is not None:
        return "within", (
            f"study {study.name}: every participant runs every condition, order {study.order}"
        )
    spans: dict[str, set[str]] = {}
    for t in trials:
        if t.session.condition:
            spans.setdefault(t.session.operator_id, set()).add(t.session.condition)
    crossing = sorted(p for p, conditions in spans.items() if len(conditions) > 1)
    if crossing:
        return "within", (
            f"{len(crossing)} of {len(spans)} participants ran more than one condition "
            "(give --study FILE for the study's name and progress)"
        )
    return "between", "no participant ran more than one condition"


def _compare(
    first: str,
    second: str,
    pairs: Sequence[tuple[Cell | None, Cell | None]],
    params: PairedParams,
) -> PairedComparison:
    tests = {}
    for metric in PAIRED_METRICS:
        a = [c.values[metric] if c else math.nan for c, _ in pairs]
        b = [c.values[metric] if c else math.nan for _, c in pairs]
        tests[metric] = paired_test(a, b, params)
    return PairedComparison(first, second, tests)


def _left_out(trial: TrialAudit, participants: Sequence[str], study: str | None) -> str | None:
    if not trial.session.condition:
        return "no condition"
    if trial.row.mode == "practice":
        return PRACTICE
    if study is not None and trial.session.operator_id not in participants:
        return f"not a participant of study {study}"
    return None


@dataclass(frozen=True)
class _Sorted:
    kept: list[TrialAudit]
    left_out: dict[str, int]
    orders: dict[str, tuple[str, ...]]


def _sort(trials: Sequence[TrialAudit], study: StudyProgress | None) -> _Sorted:
    """The trials the cells hold, those left out (counted by reason), and each
    participant's conditions in the order their trials ran (practice included)."""
    planned = [p.participant for p in study.participants] if study else []
    left_out: dict[str, int] = {}
    kept: list[TrialAudit] = []
    orders: dict[str, list[str]] = {}
    for t in trials:
        reason = _left_out(t, planned, study.name if study else None)
        if reason in (None, PRACTICE):
            order = orders.setdefault(t.session.operator_id, [])
            if t.session.condition not in order:
                order.append(t.session.condition)
        if reason is None:
            kept.append(t)
        else:
            left_out[reason] = left_out.get(reason, 0) + 1
    return _Sorted(kept, left_out, {p: tuple(order) for p, order in orders.items()})


def within_subject(
    trials: Sequence[TrialAudit],
    design_reason: str,
    params: PairedParams,
    study: StudyProgress | None,
) -> WithinSubject:
    """The participant x condition cells and every paired test."""
    sorted_ = _sort(trials, study)
    kept, orders = sorted_.kept, sorted_.orders
    planned = [p.participant for p in study.participants] if study else []
    seen = [t.session.operator_id for t in kept]
    participants = tuple(dict.fromkeys([*planned, *seen]))
    conditions = tuple(
        dict.fromkeys([*(study.conditions if study else ()), *(t.session.condition for t in kept)])
    )
    cells = {}
    for participant in participants:
        for condition in conditions:
            members = [
                t
                for t in kept
                if t.session.operator_id == participant and t.session.condition == condition
            ]
            if members:
                cells[participant, condition] = cell_of(participant, condition, members)
    pairs = tuple(
        _compare(a, b, [(cells.get((p, a)), cells.get((p, b))) for p in participants], params)
        for i, a in enumerate(conditions)
        for b in conditions[i + 1 :]
    )
    by_position = [
        (cells.get((p, order[0])), cells.get((p, order[1])))
        for p, order in orders.items()
        if len(order) > 1
    ]
    return WithinSubject(
        design_reason=design_reason,
        participants=participants,
        conditions=conditions,
        cells=cells,
        orders=orders,
        pairs=pairs,
        order_effect=_compare("first", "second", by_position, params),
        left_out=sorted_.left_out,
        params=params,
        study=study,
    )

"""Statistics of the valid trials: success rate with its Wilson 95 % interval, and
descriptive statistics (mean +- sample SD, median [IQR]) of each metric (paper §IV-D, V).

Outcome statistics count the valid trials (successes + timeouts); the Table I metrics
describe the valid successful trials; sampling figures describe all valid trials.
Groups (session, mode, level, operator) are reported where the trials hold more than one
value of that key: each group's dispositions count all its trials, its statistics its
valid ones.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

from workcell.audit.counts import DispositionCounts
from workcell.audit.task_funnel import trial_stage_counts, trial_stages_reached
from workcell.audit.trial_audit import TrialAudit
from workcell.metrics import Descriptive, describe, wilson_interval

SUCCESS_METRICS: dict[str, str] = {
    "completion_time_s": "s",
    "path_length_m": "m",
    "smoothness": "rad/sample^2",
    "active_ratio": "share 0-1",
}
"""Table I: metric -> unit, described over valid successful trials."""

SAMPLING_METRICS: dict[str, str] = {"hz_wall": "Hz", "hz_sim": "Hz", "max_gap_s": "s"}
"""Sampling figures (paper §V-D): metric -> unit, described over all valid trials."""


@dataclass(frozen=True)
class SuccessRate:
    """``successes`` of ``n`` valid trials; ``rate``, ``low``, ``high`` shares 0-1 (NaN
    for n = 0), the interval Wilson's at 95 %."""

    successes: int
    n: int
    rate: float
    low: float
    high: float

    @classmethod
    def of(cls, trials: Sequence[TrialAudit]) -> SuccessRate:
        valid = [t for t in trials if t.disposition.included]
        successes = sum(t.row.outcome == "success" for t in valid)
        low, high = wilson_interval(successes, len(valid))
        rate = successes / len(valid) if valid else math.nan
        return cls(successes, len(valid), rate, low, high)


def metric_values(trials: Sequence[TrialAudit], name: str) -> list[float]:
    """The recomputed ``name`` of each trial (NaN where undefined)."""
    values = (getattr(t.metrics, name) for t in trials)
    return [math.nan if v is None else float(v) for v in values]


def success_metrics(trials: Sequence[TrialAudit]) -> dict[str, Descriptive]:
    successes = [t for t in trials if t.valid_success]
    return {name: describe(metric_values(successes, name)) for name in SUCCESS_METRICS}


def sampling_metrics(trials: Sequence[TrialAudit]) -> dict[str, Descriptive]:
    valid = [t for t in trials if t.disposition.included]
    return {name: describe(metric_values(valid, name)) for name in SAMPLING_METRICS}


@dataclass(frozen=True)
class GroupStats:
    """The trials sharing one value of a grouping key: their dispositions, and the
    statistics of the valid ones."""

    value: str
    counts: DispositionCounts
    rate: SuccessRate
    metrics: dict[str, Descriptive]
    task_stages: dict[str, int]
    """How many of the group's trials got to each stage and no further (all trials)."""
    task_stages_reached: dict[str, int]
    """How many of them reached each stage or went further in their own task."""

    @classmethod
    def of(cls, value: str, members: Sequence[TrialAudit]) -> GroupStats:
        return cls(
            value,
            DispositionCounts.of(members),
            SuccessRate.of(members),
            success_metrics(members),
            task_stages_of(members),
            trial_stages_reached(members),
        )


def task_stages_of(trials: Sequence[TrialAudit]) -> dict[str, int]:
    """How many trials got to each stage and no further (trials not read count nowhere)."""
    return trial_stage_counts(trials)  # in their task's order


GROUP_KEYS: dict[str, Callable[[TrialAudit], str]] = {
    "session": lambda t: t.row.session_id,
    "mode": lambda t: t.row.mode,
    "level": lambda t: "-" if t.row.level is None else str(t.row.level),
    "operator": lambda t: t.session.operator_id,
}


def grouped(trials: Sequence[TrialAudit]) -> dict[str, list[GroupStats]]:
    """Per grouping key with more than one value among the trials: one entry per value,
    in order of first appearance (session order)."""
    out: dict[str, list[GroupStats]] = {}
    for key, of in GROUP_KEYS.items():
        values = list(dict.fromkeys(of(t) for t in trials))
        if len(values) < 2:
            continue
        out[key] = [GroupStats.of(value, [t for t in trials if of(t) == value]) for value in values]
    return out

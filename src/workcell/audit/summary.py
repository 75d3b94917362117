"""summary.json: every count, statistic, parameter and finding of an audit, as JSON.

Undefined numbers (NaN) are written as null. Nothing in it depends on when the audit ran,
so two audits of the same data (a store and its CSV export) write the same summary apart
from ``source``.
"""

from __future__ import annotations

import math
from collections import Counter
from dataclasses import asdict
from typing import Any

from workcell import __version__
from workcell.audit.comparison import CAVEAT, Comparison, compare_result, result_study
from workcell.audit.config import AUDIT_VERSION
from workcell.audit.counts import DispositionCounts
from workcell.audit.flags import FLAG_NAMES
from workcell.audit.interventions import (
    INTERVENTIONS_VERSION,
    InterventionGroup,
    intervention_groups,
)
from workcell.audit.ladder import LADDER_VERSION, Rung, audit_ladder
from workcell.audit.oscillation import OscillationCriteria
from workcell.audit.paired import PairedComparison, WithinSubject
from workcell.audit.run import AuditResult
from workcell.audit.stats import (
    SAMPLING_METRICS,
    SUCCESS_METRICS,
    GroupStats,
    SuccessRate,
    grouped,
    sampling_metrics,
    success_metrics,
    task_stages_of,
)
from workcell.audit.study_progress import StudyProgress
from workcell.audit.task_funnel import task_funnels, trial_stages_reached
from workcell.audit.task_stages import TASK_STAGES_VERSION, at_least
from workcell.metrics import METRIC_DEFINITIONS, METRICS_VERSION, Descriptive

FORMAT = "workcell-audit-summary"


def clean(value: Any) -> Any:
    """``value`` with every non-finite float replaced by None (JSON has no NaN)."""
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if isinstance(value, dict):
        return {k: clean(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [clean(v) for v in value]
    return value


def _rate(rate: SuccessRate) -> dict[str, Any]:
    return {**asdict(rate), "confidence": 0.95, "interval": "wilson"}


def _described(stats: dict[str, Descriptive], units: dict[str, str]) -> dict[str, Any]:
    return {name: {"unit": units[name], **asdict(d)} for name, d in stats.items()}


def _group(group: GroupStats) -> dict[str, Any]:
    return {
        "value": group.value,
        "counts": asdict(group.counts),
        "success_rate": _rate(group.rate),
        **_described(group.metrics, SUCCESS_METRICS),
        "task_stages": _stages(group.task_stages, group.task_stages_reached),
    }


def _stages(counts: dict[str, int], reached: dict[str, int] | None = None) -> dict[str, Any]:
    """Trials per stage they got to and no further, and per stage they got to or beyond
    (``reached``: in each trial's own task, when the trials are of several tasks)."""
    return {"ended_at": counts, "reached": at_least(counts) if reached is None else reached}


def _ladder(rungs: list[Rung]) -> dict[str, Any]:
    """``summary["ladder"]``: one entry per operator, task and named world."""
    return {
        "definition_version": LADDER_VERSION,
        "rungs": [{**asdict(r), "confidence": 0.95, "interval": "wilson"} for r in rungs],
    }


def _interventions(groups: list[InterventionGroup]) -> dict[str, Any]:
    """``summary["interventions"]``: per driver, and per driver and person."""
    return {
        "definition_version": INTERVENTIONS_VERSION,
        "groups": [
            {
                **asdict(g),
                "alone": {**asdict(g.alone), "rate": g.alone.rate},
                "corrected": {**asdict(g.corrected), "rate": g.corrected.rate},
                "confidence": 0.95,
                "interval": "wilson",
            }
            for g in groups
        ],
    }


def _comparison(comparison: Comparison) -> dict[str, Any]:
    """``summary["comparison"]``: groups, tests between every two, learning curves."""
    return {
        "by": comparison.by,
        "groups": [_group(g) for g in comparison.groups],
        "pairs": [
            {
                "first": pair.first,
                "second": pair.second,
                "success": {"test": "fisher_exact_two_sided", **asdict(pair.success)},
                "metrics": {
                    rank.metric: {"test": "mann_whitney_u_two_sided", **asdict(rank)}
                    for rank in pair.ranks
                },
            }
            for pair in comparison.pairs
        ],
        "learning_curves": {
            operator: [asdict(a) for a in attempts]
            for operator, attempts in comparison.learning.items()
        },
        "caveat": CAVEAT,
        "design": comparison.design,
        "design_reason": comparison.design_reason,
        "paired": None if comparison.within is None else _within(comparison.within),
    }


def _within(within: WithinSubject) -> dict[str, Any]:
    """``summary["comparison"]["paired"]``: the participant x condition cells and every
    paired test (Wilcoxon signed-rank, rank-biserial r with its bootstrap interval)."""

    def tests(pair: PairedComparison) -> dict[str, Any]:
        return {
            "first": pair.first,
            "second": pair.second,
            "metrics": {
                metric: {"test": "wilcoxon_signed_rank_two_sided", **asdict(test)}
                for metric, test in pair.tests.items()
            },
        }

    return {
        "participants": list(within.participants),
        "conditions": list(within.conditions),
        "cells": [
            {
                "participant": cell.participant,
                "condition": cell.condition,
                "trials": cell.trials,
                "valid": cell.valid,
                "successes": cell.successes,
                **cell.values,
            }
            for cell in within.cells.values()
        ],
        "orders": {p: list(order) for p, order in within.orders.items()},
        "pairs": [tests(pair) for pair in within.pairs],
        "order_effect": tests(within.order_effect),
        "left_out": within.left_out,
        "bootstrap": asdict(within.params),
    }


def _study(study: StudyProgress) -> dict[str, Any]:
    return {
        "name": study.name,
        "order": study.order,
        "conditions": list(study.conditions),
        "sessions_planned": study.planned,
        "sessions_done": study.done,
        "participants": [asdict(p) for p in study.participants],
        "other_operators": list(study.others),
    }


def parameters(result: AuditResult) -> dict[str, Any]:
    """The audit's parameters, with the oscillation criteria derived at each session rate."""
    described = result.config.describe()
    by_rate: dict[str, Any] = {}
    for rate in sorted({s.rate_hz for s in result.sessions}):
        criteria = OscillationCriteria.of(result.config.oscillation, rate)
        by_rate[f"{rate:g}"] = None if criteria is None else criteria.describe()
    described["arm_oscillation_criteria_by_rate_hz"] = by_rate
    return described


def build_summary(result: AuditResult) -> dict[str, Any]:
    trials = result.trials
    valid = [t for t in trials if t.disposition.included]
    flagged = Counter(f.name for t in trials for f in t.flags)
    flagged_valid = Counter(f.name for t in valid for f in t.flags)
    gaps = [t.metrics.max_gap_s for t in valid if math.isfinite(t.metrics.max_gap_s)]
    summary = {
        "format": FORMAT,
        "audit_version": AUDIT_VERSION,
        "metrics_version": METRICS_VERSION,
        "software_version": __version__,
        "source": {"kind": result.source_kind, "path": result.source_path},
        "parameters": parameters(result),
        "metric_definitions": METRIC_DEFINITIONS,
        "sessions": [
            {
                "session_id": s.session_id,
                "mode": s.mode,
                "operator_id": s.operator_id,
                "rate_hz": s.rate_hz,
                "thresholds": asdict(s.thresholds),
                "metrics_version": s.metrics_version,
                "trials": sum(t.row.session_id == s.session_id for t in trials),
            }
            for s in result.sessions
        ],
        "frames": result.frames_read,
        "counts": asdict(DispositionCounts.of(trials)),
        "success_rate": _rate(SuccessRate.of(trials)),
        "metrics": _described(success_metrics(trials), SUCCESS_METRICS),
        "sampling": {
            **_described(sampling_metrics(trials), SAMPLING_METRICS),
            "largest_gap_s": max(gaps) if gaps else None,
        },
        "task_stages": {
            "definition_version": TASK_STAGES_VERSION,
            **_stages(task_stages_of(trials), trial_stages_reached(trials)),
            "by_task": {
                f.task: {"stages": list(f.stages), "unknown": f.unknown, **_stages(f.ended_at)}
                for f in task_funnels(trials)
            },
        },
        "flags": {
            name: {"trials": flagged[name], "valid_trials": flagged_valid[name]}
            for name in FLAG_NAMES
        },
        "crosscheck": {
            "trials": sum(t.row.outcome is not None for t in trials),
            "trials_with_mismatch": sum(bool(t.mismatches) for t in trials),
        },
        "groups": {key: [_group(g) for g in groups] for key, groups in grouped(trials).items()},
        "findings": [asdict(f) for f in result.findings],
    }
    rungs = audit_ladder(trials)
    if rungs:
        summary["ladder"] = _ladder(rungs)
    corrections = intervention_groups(trials, result.switches)
    if corrections:
        summary["interventions"] = _interventions(corrections)
    comparison = compare_result(result)
    if comparison is not None:
        summary["comparison"] = _comparison(comparison)
    study = result_study(result)
    if study is not None:
        summary["study"] = _study(study)
    cleaned: dict[str, Any] = clean(summary)
    return cleaned

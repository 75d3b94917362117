"""The report's tables: Table I, sampling, groups, findings, trials and parameters."""

from __future__ import annotations

import json
from collections.abc import Sequence
from typing import Any

from workcell.audit.counts import DispositionCounts
from workcell.audit.findings import Finding
from workcell.audit.html_parts import DASH, Raw, esc, mean_sd, median_iqr, number, table
from workcell.audit.stats import GroupStats, sampling_metrics, success_metrics
from workcell.audit.trial_audit import TrialAudit
from workcell.metrics import Descriptive

TABLE_I: tuple[tuple[str, str, float, int], ...] = (
    ("completion_time_s", "Completion time (s)", 1.0, 2),
    ("path_length_m", "TCP path (m)", 1.0, 2),
    ("smoothness", "Smoothness (rad/sample²)", 1.0, 4),
    ("active_ratio", "Active-action (%)", 100.0, 2),
)
SAMPLING: tuple[tuple[str, str, int], ...] = (
    ("hz_wall", "Realized rate, wall clock (Hz)", 3),
    ("hz_sim", "Realized rate, sim clock (Hz)", 3),
    ("max_gap_s", "Max inter-frame gap, wall clock (s)", 3),
)
MAX_FINDINGS_SHOWN = 2000


def _failures(n: int) -> str:
    """``, 2 failed``: trials their task's judge failed, where there are any."""
    return f", {n} failed" if n else ""


def counts_table(c: DispositionCounts) -> str:
    def causes(d: dict[str, int]) -> str:
        return ", ".join(f"{k}: {v}" for k, v in d.items()) or DASH

    rows = [
        ("raw trials", c.raw, ""),
        ("excluded: incomplete", c.incomplete, causes(c.incomplete_causes)),
        (
            "complete",
            c.complete,
            f"{c.complete_successes} successes, {c.complete_timeouts} timeouts"
            + _failures(c.complete_failures),
        ),
        ("excluded: low-quality success", c.excluded_low_quality, causes(c.low_quality_causes)),
        ("excluded by reviewer", c.excluded_by_reviewer, ""),
        ("included by reviewer against a rule", c.included_by_reviewer, ""),
        (
            "valid",
            c.valid,
            f"{c.valid_successes} successes, {c.valid_timeouts} timeouts"
            + _failures(c.valid_failures),
        ),
        (
            "valid, flagged and marked",
            c.marked_successes + c.marked_timeouts + c.marked_failures,
            f"{c.marked_successes} successes, {c.marked_timeouts} timeouts"
            + _failures(c.marked_failures),
        ),
    ]
    return table(("stage", "trials", "detail"), rows)


def _metric_rows(stats: dict[str, Descriptive]) -> list[tuple[object, ...]]:
    return [
        (
            label,
            stats[name].n,
            mean_sd(stats[name], scale, digits),
            median_iqr(stats[name], scale, digits),
        )
        for name, label, scale, digits in TABLE_I
    ]


def table_one(trials: Sequence[TrialAudit]) -> str:
    return table(
        ("measure", "n", "mean ± SD", "median [IQR]"), _metric_rows(success_metrics(trials))
    )


def sampling_table(trials: Sequence[TrialAudit]) -> str:
    stats = sampling_metrics(trials)
    rows = [
        (
            label,
            stats[name].n,
            mean_sd(stats[name], digits=digits),
            median_iqr(stats[name], digits=digits),
            number(stats[name].maximum, digits),
        )
        for name, label, digits in SAMPLING
    ]
    return table(("measure (valid trials)", "n", "mean ± SD", "median [IQR]", "max"), rows)


def percent_interval(rate: float, low: float, high: float) -> str:
    """'69.81 % [56.46, 80.48]' from shares 0-1."""
    return f"{number(100 * rate, 2)} % [{number(100 * low, 2)}, {number(100 * high, 2)}]"


def groups_section(groups: dict[str, list[GroupStats]]) -> str:
    if not groups:
        return "<p>All trials share one session, mode, level and operator.</p>"
    return "".join(
        f"<h3>By {esc(key)}</h3>" + group_table(key, stats) for key, stats in groups.items()
    )


def group_table(key: str, stats: Sequence[GroupStats]) -> str:
    """One row per group: dispositions, success rate with its interval, median metrics."""
    rows = []
    for g in stats:
        r = g.rate
        metric = dict(zip((m[0] for m in TABLE_I), _metric_rows(g.metrics), strict=True))
        c = g.counts
        rows.append(
            (
                g.value,
                c.raw,
                c.incomplete,
                c.excluded_low_quality + c.excluded_by_reviewer,
                r.n,
                f"{r.successes}/{r.n}",
                percent_interval(r.rate, r.low, r.high),
                metric["completion_time_s"][2],
                metric["path_length_m"][2],
            )
        )
    header = (
        key,
        "trials",
        "incomplete",
        "excluded",
        "valid",
        "successes",
        "success rate [Wilson 95 %]",
        "completion time (s)",
        "TCP path (m)",
    )
    return table(header, rows)


def findings_table(findings: Sequence[Finding]) -> str:
    if not findings:
        return "<p>No findings: every stored metric was reproduced and no flag was raised.</p>"
    rows = [
        (f.kind, f.subject, f.trial_id or DASH, f.session_id or DASH, f.message)
        for f in findings[:MAX_FINDINGS_SHOWN]
    ]
    more = len(findings) - MAX_FINDINGS_SHOWN
    note = f"<p>{more} more findings are in summary.json.</p>" if more > 0 else ""
    return table(("kind", "subject", "trial", "session", "finding"), rows, "long") + note


def _disposition_cell(t: TrialAudit) -> Raw:
    d = t.disposition
    text = esc(d.stage)
    if d.overridden and d.review is not None:
        text += (
            f' <span class="reviewer">(reviewer {esc(d.review.by)}: {esc(d.review.reason)})</span>'
        )
    elif d.review is not None:
        text += f" (reviewer {esc(d.review.by)} agrees)"
    if d.refused:
        text += f' <span class="reviewer">({esc(d.refused)})</span>'
    if d.marked:
        text += " <b>marked</b>"
    return Raw(text)


def trials_table(trials: Sequence[TrialAudit]) -> str:
    rows = []
    for i, t in enumerate(trials):
        flags = Raw(
            ", ".join(
                f'<span class="flag" title="{esc(f.detail)}">{esc(f.name)}</span>' for f in t.flags
            )
            or DASH
        )
        rows.append(
            (
                i,
                t.trial_id,
                t.row.trial_index,
                t.session.operator_id,
                t.session.condition or DASH,
                DASH if t.session.study_step is None else t.session.study_step,
                t.row.outcome or "open",
                _disposition_cell(t),
                flags,
                number(t.metrics.completion_time_s, 2),
                number(t.metrics.path_length_m, 2),
                ", ".join(m.metric for m in t.mismatches) or DASH,
            )
        )
    header = (
        "#",
        "trial",
        "index",
        "participant",
        "condition",
        "study step",
        "outcome",
        "disposition",
        "flags",
        "completion (s)",
        "path (m)",
        "metric mismatches",
    )
    return table(header, rows, "long")


def parameters_section(parameters: dict[str, Any], metric_definitions: dict[str, str]) -> str:
    """The parameters as JSON, each check's written definition, each metric's definition."""
    values = {k: v for k, v in parameters.items() if k != "definitions"}
    checks = "".join(
        f"<h3>{esc(name)}</h3><pre>{esc(text)}</pre>"
        for name, text in parameters["definitions"].items()
    )
    metrics = table(("metric", "definition"), list(metric_definitions.items()))
    return (
        f"<h3>Parameters</h3><pre><code>{esc(json.dumps(values, indent=2))}</code></pre>"
        f"{checks}<h3>Metrics</h3>{metrics}"
    )

"""report.html: one self-contained page (figures as base64 PNG, inline CSS, no links out)
that a reviewer can read offline."""

from __future__ import annotations

from collections.abc import Sequence

from workcell import __version__
from workcell.audit.comparison import compare_result, result_study
from workcell.audit.config import AUDIT_VERSION
from workcell.audit.counts import DispositionCounts
from workcell.audit.figures import RenderedFigure
from workcell.audit.html_parts import CSS, esc, image, number
from workcell.audit.interventions import intervention_groups
from workcell.audit.ladder import audit_ladder
from workcell.audit.report_comparison import comparison_section
from workcell.audit.report_interventions import interventions_section
from workcell.audit.report_ladder import ladder_section
from workcell.audit.report_paired import study_section
from workcell.audit.report_sections import (
    counts_table,
    findings_table,
    groups_section,
    parameters_section,
    percent_interval,
    sampling_table,
    table_one,
    trials_table,
)
from workcell.audit.report_stages import stages_section
from workcell.audit.run import AuditResult
from workcell.audit.stats import SuccessRate, grouped
from workcell.audit.summary import parameters
from workcell.metrics import METRIC_DEFINITIONS, METRICS_VERSION


def _figure(fig: RenderedFigure) -> str:
    return (
        f'<figure id="{esc(fig.key)}">{image(fig.png, fig.title)}'
        f"<figcaption><b>{esc(fig.title)}.</b> {esc(fig.caption)}</figcaption></figure>"
    )


def _comparison(result: AuditResult, figures: dict[str, str]) -> str:
    comparison = compare_result(result)
    if comparison is None:
        study = result_study(result)
        return "" if study is None else f"<h3>Study</h3>{study_section(study)}"
    section = comparison_section(comparison, figures)
    return f"<h3>Comparison by {esc(comparison.by)}</h3>{section}"


def build_report(result: AuditResult, figures: Sequence[RenderedFigure]) -> str:
    trials = result.trials
    counts = DispositionCounts.of(trials)
    rate = SuccessRate.of(trials)
    fig = {f.key: _figure(f) for f in figures}
    rate_text = (
        f"{number(100 * rate.rate, 2)} %"
        f" <small>[{number(100 * rate.low, 2)}, {number(100 * rate.high, 2)}]</small>"
    )
    mismatched = sum(bool(t.mismatches) for t in trials)
    study = result.config.study
    study_meta = "" if study is None else f" · study <b>{esc(study.name)}</b>"
    key = "".join(
        f"<div>{label}<b>{value}</b></div>"
        for label, value in (
            ("raw trials", counts.raw),
            ("valid trials", counts.valid),
            ("successes / timeouts", f"{counts.valid_successes} / {counts.valid_timeouts}"),
            ("success rate, Wilson 95 %", rate_text),
            ("frames read", result.frames_read),
            ("metric mismatches", mismatched),
        )
    )
    body = f"""
<h1>Workcell audit</h1>
<p class="meta">{esc(result.source_kind)} <code>{esc(result.source_path)}</code> ·
{len(result.sessions)} session(s){study_meta} · workcell {esc(__version__)} ·
audit v{AUDIT_VERSION} · metrics v{esc(METRICS_VERSION)}. Every metric below was
recomputed from the frames and checked against the value stored on its trial; flags never
change outcomes; stored rows were not changed.</p>
<div class="key">{key}</div>
<h2>1. Trial disposition</h2>
{fig["flow"]}
{counts_table(counts)}
<h2>2. Outcomes</h2>
<p>Success rate over the valid trials: {rate.successes}/{rate.n} =
{esc(percent_interval(rate.rate, rate.low, rate.high))} (Wilson 95 % confidence interval).
Repeated trials of one operator are attempts, not independent people.</p>
{fig["outcomes"]}
{stages_section(trials, grouped(trials).get("operator", []))}
{ladder_section(audit_ladder(trials), fig.get("ladder", ""))}
{interventions_section(intervention_groups(trials, result.switches))}
<h2>3. Successful demonstrations (Table I)</h2>
{table_one(trials)}
{fig["distributions"]}
<h2>4. Trajectory morphology</h2>
{fig["trajectories"]}
<h2>5. Sampling continuity</h2>
{sampling_table(trials)}
{fig["sampling"]}
<h2>6. Groups</h2>
{groups_section(grouped(trials))}
{_comparison(result, fig)}
<h2>7. Findings</h2>
{findings_table(result.findings)}
<h2>8. Trials in session order</h2>
{trials_table(trials)}
<h2>9. Parameters and definitions</h2>
{parameters_section(parameters(result), METRIC_DEFINITIONS)}
"""
    return (
        '<!DOCTYPE html>\n<html lang="en"><head><meta charset="utf-8">'
        '<meta name="viewport" content="width=device-width, initial-scale=1">'
        f"<title>Workcell audit</title><style>{CSS}</style></head>"
        f"<body>{body}</body></html>\n"
    )

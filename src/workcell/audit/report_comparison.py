"""report.html's comparison section (``workcell audit --by operator|condition``): the
groups, the tests between every two of them (pooled; within participants on a
within-subject design, :mod:`workcell.audit.report_paired`), the learning curves and the
caveat."""

from __future__ import annotations

import math

from workcell.audit.comparison import (
    CAVEAT,
    RANKED_METRICS,
    Comparison,
    PairComparison,
    RankTest,
)
from workcell.audit.html_parts import esc, number, table
from workcell.audit.report_paired import study_section, within_section
from workcell.audit.report_sections import group_table


def _p(value: float) -> str:
    return "p < 0.001" if value < 0.001 else f"p = {number(value, 3)}"


def _success_cell(pair: PairComparison) -> str:
    test = pair.success
    if math.isnan(test.p_value):  # a group has no valid trial
        return "—"
    points = 100 * test.risk_difference
    return (
        f"{_p(test.p_value)}; difference {points:+.1f} points; "
        f"odds ratio {number(test.odds_ratio, 3)}"
    )


def _rank_cell(rank: RankTest) -> str:
    unit = RANKED_METRICS[rank.metric][1]
    medians = f"median {number(rank.median_first, 3)} vs {number(rank.median_second, 3)} {unit}"
    if math.isnan(rank.p_value):
        return f"{medians} (n = {rank.n_first}, {rank.n_second}: no test)"
    return (
        f"{medians}; U = {number(rank.u, 4)}, {_p(rank.p_value)}, "
        f"rank-biserial r = {rank.rank_biserial:+.2f} (n = {rank.n_first}, {rank.n_second})"
    )


def comparison_section(comparison: Comparison, figures: dict[str, str]) -> str:
    """The section's HTML; ``figures`` holds the rendered ``comparison`` and ``learning``
    (and ``paired`` on a within-subject design)."""
    by = comparison.by
    if comparison.within is not None:
        return f"""
{within_section(comparison.within, figures["paired"])}
<h4>Conditions pooled (descriptive)</h4>
<p>Every trial of each condition, whoever ran it: not tested, as the design pairs them.</p>
{group_table(by, comparison.groups)}
{figures["comparison"]}
<h4>Learning curves</h4>
{figures["learning"]}
"""
    study = study_section(comparison.study) if comparison.study is not None else ""
    header = (
        "first",
        "second",
        "success (Fisher's exact)",
        *(f"{name} (Mann-Whitney U)" for name, _ in RANKED_METRICS.values()),
    )
    rows = [
        (pair.first, pair.second, _success_cell(pair), *(_rank_cell(r) for r in pair.ranks))
        for pair in comparison.pairs
    ]
    tests = (
        table(header, rows)
        if rows
        else f"<p>Only one {esc(by)} among these trials: nothing to compare.</p>"
    )
    return f"""{study}
<p>Design: {esc(comparison.design)}-subject ({esc(comparison.design_reason)}).
Trials grouped by {esc(by)}. Success compares valid successes against valid failures
(Fisher's exact test, two-sided; difference = first minus second); times and paths compare
the valid successes (Mann-Whitney U, two-sided; U of the first group; rank-biserial
r = 2U/(n1 n2) - 1, positive when the first group's values are larger).
<b>{esc(CAVEAT)}</b></p>
{group_table(by, comparison.groups)}
{figures["comparison"]}
<h4>Tests between {esc(by)}s</h4>
{tests}
<h4>Learning curves</h4>
{figures["learning"]}
"""

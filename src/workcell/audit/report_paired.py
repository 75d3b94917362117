"""report.html's within-subject comparison (``workcell audit --by condition`` on a study
where every participant runs every condition): the study's name and progress, the
participant x condition table, the paired tests between conditions and the order effect."""

from __future__ import annotations

import math

from workcell.audit.html_parts import DASH, esc, number, table
from workcell.audit.paired import PAIRED_METRICS, PairedComparison, WithinSubject
from workcell.audit.paired_text import (
    comparison_label,
    effect_text,
    medians_text,
    wilcoxon_text,
)
from workcell.audit.study_progress import StudyProgress
from workcell.audit.wilcoxon import MIN_PAIRS


def study_section(study: StudyProgress) -> str:
    """The study's name and how much of each participant's plan is done."""
    rows = [
        (p.participant, " → ".join(p.order), f"{p.done}/{p.planned}") for p in study.participants
    ]
    others = (
        f"<p>Sessions of operators the study does not hold: {esc(', '.join(study.others))}.</p>"
        if study.others
        else ""
    )
    return f"""
<p><b>Study {esc(study.name)}</b>: conditions {esc(", ".join(study.conditions))}, order
{esc(study.order)}; {len(study.participants)} participants, {study.done} of {study.planned}
planned sessions done (a planned session is done when a completed session of that
participant, condition and seed is among the audited ones).</p>
{table(("participant", "conditions in their order", "sessions done"), rows)}
{others}"""


def _cells_table(within: WithinSubject) -> str:
    header = ["participant"]
    for condition in within.conditions:
        header += [f"{condition}: trials", "valid successes", "median completion (s)"]
    rows = []
    for participant in within.participants:
        row: list[object] = [participant]
        for condition in within.conditions:
            cell = within.cells.get((participant, condition))
            if cell is None:
                row += [0, DASH, DASH]
                continue
            time = cell.values["completion_time_s"]
            row += [
                cell.trials,
                f"{cell.successes}/{cell.valid}",
                number(time, 2) if math.isfinite(time) else DASH,
            ]
        rows.append(row)
    return table(header, rows)


def _tests_rows(pair: PairedComparison, label: str, confidence: float) -> list[tuple[str, ...]]:
    return [
        (
            label,
            PAIRED_METRICS[metric][0],
            str(test.n_pairs),
            medians_text(metric, test) if test.n_pairs else DASH,
            wilcoxon_text(test),
            effect_text(test, confidence) or DASH,
        )
        for metric, test in pair.tests.items()
    ]


def within_section(within: WithinSubject, figure: str) -> str:
    params = within.params
    confidence = params.confidence
    compared = [(p, comparison_label(p, False)) for p in within.pairs]
    compared.append((within.order_effect, comparison_label(within.order_effect, True)))
    rows = [row for pair, label in compared for row in _tests_rows(pair, label, confidence)]
    left = ", ".join(f"{n} {reason}" for reason, n in within.left_out.items())
    left_text = f" Left out of the table and the tests: {esc(left)} trials." if left else ""
    study = study_section(within.study) if within.study is not None else ""
    header = (
        "comparison",
        "per participant",
        "pairs",
        "medians (first vs second)",
        "Wilcoxon signed-rank",
        "effect size",
    )
    return f"""
{study}
<p><b>Design: within-subject</b> ({esc(within.design_reason)}): every participant's
conditions are compared with each other, one value per participant and condition: the
success rate of their valid trials, the median completion time and median TCP path of their
valid successes (practice trials left out).{left_text}</p>
<h4>Participant &times; condition</h4>
{_cells_table(within)}
{figure}
<h4>Paired tests</h4>
<p>Wilcoxon signed-rank test (two-sided) on the participants' differences, first minus
second; participants without a value in both are left out, those without a difference
dropped (Wilcoxon's convention); exact for up to 50 differences without ties, an
exhaustive permutation of signs with ties (up to 13), else the normal approximation. With
n differences the smallest two-sided p possible is 2/2<sup>n</sup>. A test needs
{MIN_PAIRS} participants with a value in both and one difference that is not 0. Effect
size: the matched-pairs rank-biserial correlation
r = (T+ &minus; T&minus;)/(T+ + T&minus;), positive when the first values are larger; its
{100 * confidence:g} % interval is the percentile bootstrap over participants
({params.resamples} draws of the participants with replacement, numpy generator seeded
{params.seed}): rough with few participants. The order effect compares each participant's
first condition with their second, whatever they were.</p>
{table(header, rows)}
"""

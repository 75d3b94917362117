"""The within-subject comparison in words: the printed summary's lines and the report's
cells say the same (never "nan": a value that is missing is named as missing)."""

from __future__ import annotations

import math

from workcell.audit.paired import PAIRED_METRICS, Cell, PairedComparison, WithinSubject
from workcell.audit.wilcoxon import PairedTest


def _value(metric: str, value: float) -> str:
    _, unit, scale = PAIRED_METRICS[metric]
    if unit == "points":
        return f"{scale * value:.0f} %"
    return f"{scale * value:.3g} {unit}"


def _difference(metric: str, value: float) -> str:
    _, unit, scale = PAIRED_METRICS[metric]
    if unit == "points":
        return f"{scale * value:+.0f} points"
    return f"{scale * value:+.3g} {unit}"


def p_text(value: float) -> str:
    return "p < 0.001" if value < 0.001 else f"p = {value:.3g}"


def medians_text(metric: str, test: PairedTest) -> str:
    """``median 24.1 s vs 31 s, difference -6.9 s`` (the participants with both)."""
    return (
        f"median {_value(metric, test.median_first)} vs {_value(metric, test.median_second)}, "
        f"difference {_difference(metric, test.median_difference)}"
    )


def wilcoxon_text(test: PairedTest) -> str:
    """``Wilcoxon p = 0.125 (exact; n = 4, T+ = 0, T- = 10; smallest p possible 0.125)``,
    or why there is no test."""
    if test.missing is not None:
        return test.missing
    return (
        f"Wilcoxon {p_text(test.p_value)} ({test.method}; n = {test.n_nonzero}"
        f"{_zeros(test)}, T+ = {test.t_plus:g}, T- = {test.t_minus:g}; smallest p possible "
        f"{test.smallest_p:.3g})"
    )


def effect_text(test: PairedTest, confidence: float) -> str:
    """``rank-biserial r = -1.00 [95 % CI -1.00, -1.00]`` ("" without a test)."""
    if test.missing is not None:
        return ""
    return (
        f"rank-biserial r = {test.rank_biserial:+.2f} "
        f"[{100 * confidence:g} % CI {test.low:+.2f}, {test.high:+.2f}]"
    )


def test_text(metric: str, test: PairedTest, confidence: float) -> str:
    """The medians, the test and the effect size in one line."""
    if test.n_pairs == 0:
        return wilcoxon_text(test)
    effect = effect_text(test, confidence)
    return f"{medians_text(metric, test)}; {wilcoxon_text(test)}" + (
        f", {effect}" if effect else ""
    )


def _zeros(test: PairedTest) -> str:
    zeros = test.n_pairs - test.n_nonzero
    return f" of {test.n_pairs}, {zeros} without a difference" if zeros else ""


def cell_text(cell: Cell | None) -> str:
    """``2/2 valid successes of 2 trials, median 24.1 s``, or ``no trials``."""
    if cell is None:
        return "no trials"
    time = cell.values["completion_time_s"]
    median = f", median {time:.3g} s" if math.isfinite(time) else ""
    return f"{cell.successes}/{cell.valid} valid successes of {cell.trials} trials{median}"


def comparison_label(pair: PairedComparison, order_effect: bool) -> str:
    if order_effect:
        return "order: first vs second condition each participant ran"
    return f"{pair.first} vs {pair.second}"


def paired_lines(within: WithinSubject) -> list[str]:
    """The printed summary's lines: the design, the study's progress, each participant's
    cells, and every paired test."""
    lines = [f"  design: within-subject ({within.design_reason}); paired tests over participants"]
    if within.study is not None:
        lines.append(f"  {within.study.text()}")
    for participant in within.participants:
        cells = "; ".join(
            f"{condition} {cell_text(within.cells.get((participant, condition)))}"
            for condition in within.conditions
        )
        lines.append(f"  {participant}: {cells}")
    if within.left_out:
        left = ", ".join(f"{n} {reason}" for reason, n in within.left_out.items())
        lines.append(f"  left out of the participant x condition table: {left}")
    confidence = within.params.confidence
    for pair, is_order in [*((p, False) for p in within.pairs), (within.order_effect, True)]:
        lines.append(f"  {comparison_label(pair, is_order)} (paired, per participant):")
        for metric, test in pair.tests.items():
            lines.append(f"    {PAIRED_METRICS[metric][0]}: {test_text(metric, test, confidence)}")
    return lines

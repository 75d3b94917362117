"""The comparison's figures: per group the success rate with its Wilson 95 % interval and
the valid successes' completion times and path lengths; per participant the learning
curve (completion time over their trials in order, failures marked)."""

from __future__ import annotations

import math

import numpy as np

from workcell.audit.comparison import RANKED_METRICS, Comparison
from workcell.audit.figures.canvas import SUCCESS, empty, figure, png

_PALETTE = ("#1565c0", "#2e7d32", "#e07b00", "#6a1b9a", "#c62828", "#00838f", "#5d4037")


def short(label: str, width: int = 18) -> str:
    return label if len(label) <= width else label[: width - 1] + "…"


def draw_comparison(comparison: Comparison, values: dict[str, dict[str, list[float]]]) -> bytes:
    """``values``: :func:`~workcell.audit.comparison.success_values` of the trials."""
    groups = comparison.groups
    names = [short(g.value) for g in groups]
    positions = np.arange(len(groups))
    with figure(9.6, 3.4) as fig:
        rate_ax, *metric_axes = fig.subplots(1, 1 + len(RANKED_METRICS))
        rates = [100 * g.rate.rate if g.rate.n else math.nan for g in groups]
        low = [
            r - 100 * g.rate.low if g.rate.n else 0.0 for r, g in zip(rates, groups, strict=True)
        ]
        high = [
            100 * g.rate.high - r if g.rate.n else 0.0 for r, g in zip(rates, groups, strict=True)
        ]
        rate_ax.errorbar(
            positions, rates, yerr=[low, high], fmt="o", color=SUCCESS, ecolor="0.25", capsize=6
        )
        for x, g in zip(positions, groups, strict=True):
            rate_ax.annotate(
                f"{g.rate.successes}/{g.rate.n}", (x, 2), ha="center", fontsize=8, color="0.3"
            )
        rate_ax.set_ylim(0, 105)
        rate_ax.set_xlim(-0.6, len(groups) - 0.4)
        rate_ax.set_xticks(positions, names, rotation=20, ha="right")
        rate_ax.set_ylabel("success rate (%)")
        rate_ax.set_title("Success rate, Wilson 95 % CI")
        rng = np.random.default_rng(0)  # the same jitter every time: reports are reproducible
        for ax, (metric, (name, unit)) in zip(metric_axes, RANKED_METRICS.items(), strict=True):
            label = f"{name[0].upper()}{name[1:]} ({unit})"
            data = [np.asarray(values[g.value][metric], dtype=float) for g in groups]
            data = [d[np.isfinite(d)] for d in data]
            if not any(len(d) for d in data):
                empty(ax, f"{label}\nno valid successes")
                continue
            boxes = [d if len(d) else np.array([math.nan]) for d in data]
            ax.boxplot(boxes, positions=positions, widths=0.5, showfliers=False)
            for x, d, color in zip(positions, data, colors(len(groups)), strict=True):
                jitter = x + rng.uniform(-0.15, 0.15, len(d))
                ax.scatter(jitter, d, s=10, color=color, alpha=0.6, zorder=3, linewidths=0)
            ax.set_xticks(positions, names, rotation=20, ha="right")
            ax.set_title(label)
            ax.grid(axis="x", visible=False)
        return png(fig)


def colors(count: int) -> list[str]:
    return [_PALETTE[i % len(_PALETTE)] for i in range(count)]


def draw_learning(comparison: Comparison) -> bytes:
    """Per participant: completion time of each success over their trials in order (line),
    failures as crosses along the top."""
    curves = comparison.learning
    with figure(9.6, 3.4) as fig:
        times_ax, rate_ax = fig.subplots(1, 2)
        if not curves:
            empty(times_ax, "no trials")
            empty(rate_ax, "no trials")
            return png(fig)
        finite = [
            a.completion_time_s
            for attempts in curves.values()
            for a in attempts
            if math.isfinite(a.completion_time_s)
        ]
        top = max(finite) * 1.08 if finite else 1.0
        for (operator, attempts), color in zip(curves.items(), colors(len(curves)), strict=True):
            number = np.array([a.number for a in attempts])
            times = np.array([a.completion_time_s for a in attempts])
            ok = np.isfinite(times)
            times_ax.plot(
                number[ok], times[ok], "o-", color=color, ms=3, lw=1.2, label=short(operator, 28)
            )
            failed = number[~ok]
            times_ax.scatter(failed, np.full(len(failed), top), marker="x", color=color, s=18)
            successes = np.cumsum([a.outcome == "success" for a in attempts])
            rate_ax.plot(number, 100 * successes / number, color=color, lw=1.4)
        times_ax.set_xlabel("trial of the participant")
        times_ax.set_ylabel("completion time (s)")
        times_ax.set_title("Completion time (x: not a success)")
        times_ax.set_ylim(0, top * 1.06)
        rate_ax.set_xlabel("trial of the participant")
        rate_ax.set_ylabel("success rate so far (%)")
        rate_ax.set_ylim(0, 105)
        rate_ax.set_title("Cumulative success rate")
        if len(curves) <= 12:
            times_ax.legend(loc="lower left", fontsize=7.5)
        return png(fig)

"""Figure 2 (paper Fig. 5A): outcome counts of the valid trials and the success rate
with its Wilson 95 % interval. A task whose judge can end a trial as ``failed`` (a box
dropped off the pallet, say) gets a bar of its own beside the timeouts."""

from __future__ import annotations

import math

from workcell.audit.figures.canvas import FAILED, SUCCESS, TIMEOUT, empty, figure, png
from workcell.audit.stats import SuccessRate


def outcome_bars(rate: SuccessRate, failures: int = 0) -> list[tuple[str, int, str]]:
    """The bars of the counts panel, (outcome, valid trials, colour): successes and
    timeouts, and ``failures`` (how many of the valid trials their task's judge ended
    ``failed``) when there are any."""
    timeouts = rate.n - rate.successes - failures
    shown = [("success", rate.successes, SUCCESS), ("timeout", timeouts, TIMEOUT)]
    if failures:
        shown.append(("failed", failures, FAILED))
    return shown


def draw_outcomes(rate: SuccessRate, failures: int = 0) -> bytes:
    """The figure of :func:`outcome_bars` beside the success rate's interval."""
    with figure(7.2, 3.4) as fig:
        counts, share = fig.subplots(1, 2, width_ratios=(1.6, 1))
        names, values, colours = zip(*outcome_bars(rate, failures), strict=True)
        bars = counts.bar(names, values, color=colours)
        counts.bar_label(bars, padding=2)
        counts.set_ylabel("valid trials")
        counts.set_title(f"Outcomes of {rate.n} valid trials")
        counts.set_ylim(0, max(*values, 1) * 1.18)
        counts.grid(axis="x", visible=False)
        if rate.n == 0 or math.isnan(rate.rate):
            empty(share, "no valid trials")
            return png(fig)
        pct = 100 * rate.rate
        low, high = 100 * rate.low, 100 * rate.high
        share.errorbar(
            [0],
            [pct],
            yerr=[[pct - low], [high - pct]],
            fmt="o",
            color=SUCCESS,
            ecolor="0.25",
            elinewidth=1.6,
            capsize=8,
            markersize=8,
        )
        share.set_xlim(-1, 1)
        share.set_ylim(0, 105)
        share.set_xticks([])
        share.set_ylabel("success rate (%)")
        share.set_title("Success rate, Wilson 95 % CI")
        share.annotate(
            f"{pct:.2f} %\n[{low:.2f}, {high:.2f}]",
            (0, pct),
            xytext=(14, 0),
            textcoords="offset points",
            va="center",
        )
        return png(fig)

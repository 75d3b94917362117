"""Figure 2 (paper Fig. 5A): outcome counts of the valid trials and the success rate
with its Wilson 95 % interval."""

from __future__ import annotations

import math

from workcell.audit.figures.canvas import SUCCESS, TIMEOUT, empty, figure, png
from workcell.audit.stats import SuccessRate


def draw_outcomes(rate: SuccessRate) -> bytes:
    with figure(7.2, 3.4) as fig:
        counts, share = fig.subplots(1, 2, width_ratios=(1.6, 1))
        timeouts = rate.n - rate.successes
        bars = counts.bar(
            ["success", "timeout"], [rate.successes, timeouts], color=[SUCCESS, TIMEOUT]
        )
        counts.bar_label(bars, padding=2)
        counts.set_ylabel("valid trials")
        counts.set_title(f"Outcomes of {rate.n} valid trials")
        counts.set_ylim(0, max(rate.successes, timeouts, 1) * 1.18)
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

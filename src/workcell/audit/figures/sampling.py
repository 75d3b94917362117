"""Figure 5 (paper §V-D): realized sampling rate and largest inter-frame gap of every
trial, in session order."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from workcell.audit.figures.canvas import (
    ACCENT,
    EXCLUDED,
    TIMEOUT,
    empty,
    figure,
    marker_size,
    png,
)
from workcell.audit.trial_audit import TrialAudit


def _session_bounds(trials: Sequence[TrialAudit]) -> list[float]:
    ids = [t.row.session_id for t in trials]
    return [i - 0.5 for i in range(1, len(ids)) if ids[i] != ids[i - 1]]


def draw_sampling(trials: Sequence[TrialAudit], gap_periods: float) -> bytes:
    from matplotlib.ticker import (  # noqa: PLC0415
        LogLocator,
        MaxNLocator,
        NullFormatter,
        ScalarFormatter,
    )

    with figure(9.6, 5.0) as fig:
        rate_ax, gap_ax = fig.subplots(2, 1, sharex=True)
        if not trials:
            empty(rate_ax, "no trials")
            empty(gap_ax, "")
            return png(fig)
        x = np.arange(len(trials))
        size = marker_size(len(trials))
        valid = np.array([t.disposition.included for t in trials])
        wall = np.array([t.metrics.hz_wall for t in trials])
        sim = np.array([t.metrics.hz_sim for t in trials])
        gap = np.array([t.metrics.max_gap_s for t in trials])
        nominal = sorted({t.session.rate_hz for t in trials})
        for ax in (rate_ax, gap_ax):
            for bound in _session_bounds(trials):
                ax.axvline(bound, color="0.6", linestyle=":", linewidth=1)
        for values, label, colour in ((wall, "wall clock", ACCENT), (sim, "sim clock", TIMEOUT)):
            rate_ax.scatter(x[valid], values[valid], s=size, color=colour, label=label)
            if not valid.all():
                rate_ax.scatter(
                    x[~valid],
                    values[~valid],
                    s=size,
                    facecolors="none",
                    edgecolors=colour,
                    label=f"{label}, excluded trial",
                )
        for rate in nominal:
            rate_ax.axhline(rate, color="black", linestyle="--", linewidth=1)
        finite = np.concatenate([wall[np.isfinite(wall)], sim[np.isfinite(sim)]])
        if len(finite) and finite.min() > 0 and finite.max() / finite.min() > 4:
            rate_ax.set_yscale("log")
            rate_ax.yaxis.set_major_locator(LogLocator(subs=(1.0, 2.0, 5.0)))
            rate_ax.yaxis.set_major_formatter(ScalarFormatter())
            rate_ax.yaxis.set_minor_formatter(NullFormatter())
        rate_ax.set_ylabel("realized rate (Hz)")
        rate_ax.set_title("Realized sampling rate per trial (dashed: nominal)")
        rate_ax.legend(loc="upper left", bbox_to_anchor=(1.0, 1.0))
        gap_ax.scatter(x[valid], gap[valid], s=size, color=ACCENT, label="valid trial")
        if not valid.all():
            gap_ax.scatter(x[~valid], gap[~valid], s=size, color=EXCLUDED, label="excluded trial")
        for rate in nominal:
            gap_ax.axhline(gap_periods / rate, color="#c62828", linestyle="--", linewidth=1)
        gap_ax.set_ylabel("max gap, wall clock (s)")
        gap_ax.set_xlabel("trial, in session order (dotted: session boundary)")
        gap_ax.set_title(
            f"Largest inter-frame gap per trial (dashed: gap limit, {gap_periods:g} periods)"
        )
        gap_ax.legend(loc="upper left", bbox_to_anchor=(1.0, 1.0))
        gap_ax.set_ylim(bottom=0)
        gap_ax.xaxis.set_major_locator(MaxNLocator(integer=True))
        return png(fig)

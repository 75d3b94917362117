"""Figure 3 (paper Fig. 5B-E): box plots with every trial's point for completion time,
path length, smoothness and active-action ratio of the valid successful trials."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from workcell.audit.figures.canvas import SUCCESS, empty, figure, marker_size, png
from workcell.audit.stats import metric_values
from workcell.audit.trial_audit import TrialAudit

PANELS: tuple[tuple[str, str, float], ...] = (
    ("completion_time_s", "Completion time (s)", 1.0),
    ("path_length_m", "TCP-midpoint path (m)", 1.0),
    ("smoothness", "Smoothness (rad/sample²)", 1.0),
    ("active_ratio", "Active-action ratio (%)", 100.0),
)
"""metric, axis label, scale to the shown unit."""


def draw_distributions(trials: Sequence[TrialAudit]) -> bytes:
    successes = [t for t in trials if t.valid_success]
    rng = np.random.default_rng(0)  # the same jitter every time: reports are reproducible
    with figure(9.6, 3.3) as fig:
        axes = fig.subplots(1, len(PANELS))
        for ax, (name, label, scale) in zip(axes, PANELS, strict=True):
            values = np.asarray(metric_values(successes, name)) * scale
            values = values[np.isfinite(values)]
            if len(values) == 0:
                empty(ax, f"{label}\nno values")
                continue
            ax.boxplot(
                values,
                whis=1.5,
                widths=0.5,
                showfliers=False,
                medianprops={"color": "black", "linewidth": 1.5},
                boxprops={"linewidth": 1.2},
            )
            jitter = 1 + rng.uniform(-0.16, 0.16, len(values))
            ax.scatter(
                jitter,
                values,
                s=marker_size(len(values)),
                color=SUCCESS,
                alpha=0.6,
                zorder=3,
                linewidths=0,
            )
            ax.set_xticks([])
            ax.set_title(label, fontsize=9.5)
            ax.set_xlabel(f"n = {len(values)}")
            ax.grid(axis="x", visible=False)
            if name == "smoothness":
                ax.ticklabel_format(axis="y", style="sci", scilimits=(-2, 3))
        return png(fig)

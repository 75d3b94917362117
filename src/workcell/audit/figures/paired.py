"""The within-subject figure: per metric, each participant's values in every condition
joined by a line (a slope graph), the conditions in the study's order."""

from __future__ import annotations

import math

import numpy as np

from workcell.audit.figures.canvas import empty, figure, png
from workcell.audit.figures.comparison import colors, short
from workcell.audit.paired import PAIRED_METRICS, WithinSubject

DRAWN = ("success_rate", "completion_time_s", "path_length_m")


def draw_paired(within: WithinSubject) -> bytes:
    conditions = within.conditions
    positions = np.arange(len(conditions))
    palette = colors(len(within.participants))
    with figure(9.6, 3.2) as fig:
        axes = fig.subplots(1, len(DRAWN))
        for ax, metric in zip(axes, DRAWN, strict=True):
            name, unit, scale = PAIRED_METRICS[metric]
            label = f"{name[0].upper()}{name[1:]} ({'%' if unit == 'points' else unit})"
            drawn = 0
            for participant, color in zip(within.participants, palette, strict=True):
                values = np.array(
                    [
                        scale * cell.values[metric]
                        if (cell := within.cells.get((participant, c)))
                        else math.nan
                        for c in conditions
                    ]
                )
                if not np.isfinite(values).any():
                    continue
                drawn += 1
                ax.plot(
                    positions,
                    values,
                    "o-",
                    color=color,
                    ms=4,
                    lw=1.3,
                    alpha=0.85,
                    label=short(participant, 12),
                )
            if not drawn:
                empty(ax, f"{label}\nno participant has a value")
                continue
            ax.set_xticks(positions, [short(c) for c in conditions])
            ax.set_xlim(-0.4, len(conditions) - 0.6)
            ax.set_title(label)
            ax.grid(axis="x", visible=False)
            if unit == "points":
                ax.set_ylim(-5, 105)
        if len(within.participants) <= 12:
            axes[0].legend(loc="best", fontsize=7.5)
        return png(fig)

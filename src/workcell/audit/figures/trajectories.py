"""Figure 4 (paper Fig. 6): start-aligned floor-plane (x-y, z is up) TCP-midpoint paths of
temporally stratified valid successful trials, beside their path-length distribution."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING

import numpy as np

from workcell.audit.figures.canvas import SUCCESS, empty, figure, png
from workcell.audit.source import FloatArray
from workcell.audit.trial_audit import TrialAudit

if TYPE_CHECKING:
    from matplotlib.axes import Axes


def _histogram(ax: Axes, values: FloatArray) -> None:
    """Path lengths as a histogram (one bin when they are all equal) with a rug."""
    if len(values) == 0:
        return
    low, high = float(values.min()), float(values.max())
    bins = min(12, max(3, len(values) // 2))
    if high - low <= 1e-9 * max(1.0, abs(high)):
        pad = max(0.01 * abs(high), 1e-3)
        low, high, bins = low - pad, high + pad, 1
    ax.hist(values, bins=bins, range=(low, high), color=SUCCESS, alpha=0.55, edgecolor="white")


def draw_trajectories(paths: Mapping[str, FloatArray], trials: Sequence[TrialAudit]) -> bytes:
    from matplotlib import colormaps  # noqa: PLC0415
    from matplotlib.cm import ScalarMappable  # noqa: PLC0415
    from matplotlib.colors import Normalize  # noqa: PLC0415
    from matplotlib.ticker import MaxNLocator  # noqa: PLC0415

    order = {t.trial_id: i for i, t in enumerate(trials)}
    length = {t.trial_id: t.metrics.path_length_m for t in trials}
    with figure(9.6, 4.4) as fig:
        plane, spread = fig.subplots(1, 2, width_ratios=(1.7, 1))
        if not paths:
            empty(plane, "no valid successful trial")
            empty(spread, "")
            return png(fig)
        shown = sorted(paths, key=order.__getitem__)
        norm = Normalize(0, max(len(trials) - 1, 1))
        cmap = colormaps["viridis"]
        for trial_id in shown:
            xy = paths[trial_id]
            colour = cmap(norm(order[trial_id]))
            plane.plot(xy[:, 0], xy[:, 1], color=colour, linewidth=1.0, alpha=0.85)
            if len(xy):
                plane.plot(xy[-1, 0], xy[-1, 1], "o", color=colour, markersize=3)
        plane.plot(0, 0, "k+", markersize=10, markeredgewidth=1.5, label="start (aligned)")
        plane.set_aspect("equal", adjustable="datalim")
        plane.set_xlabel("x \u2212 x\u2080 (m)")
        plane.set_ylabel("y \u2212 y\u2080 (m)")
        plane.set_title(f"TCP midpoint, floor plane: {len(shown)} successful trials")
        plane.legend(loc="best")
        bar = fig.colorbar(ScalarMappable(norm=norm, cmap=cmap), ax=plane, shrink=0.85)
        bar.set_label("trial position in session order")
        bar.locator = MaxNLocator(integer=True)
        bar.update_ticks()
        values = np.array([length[t] for t in shown])
        values = values[np.isfinite(values)]
        _histogram(spread, values)
        spread.plot(values, np.zeros_like(values), "|", color="black", markersize=12)
        spread.set_xlabel("TCP-midpoint path length (m)")
        spread.set_ylabel("trials")
        spread.set_title("Path length of the trials drawn")
        spread.yaxis.set_major_locator(MaxNLocator(integer=True))
        return png(fig)

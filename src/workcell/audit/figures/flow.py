"""Figure 1 (paper Fig. 4): the disposition flow, with counts and reasons at each step."""

from __future__ import annotations

from typing import TYPE_CHECKING

from workcell.audit.counts import DispositionCounts
from workcell.audit.figures.canvas import (
    ACCENT,
    EXCLUDED,
    LOW_QUALITY,
    REVIEWER,
    SUCCESS,
    TIMEOUT,
    figure,
    png,
)

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.patches import FancyBboxPatch
    from matplotlib.text import Text

MAIN_X, SIDE_X = 0.27, 0.74
ARROW = {"arrowstyle": "-|>", "color": "0.35", "linewidth": 1.3, "shrinkA": 0, "shrinkB": 2}


def _causes(causes: dict[str, int]) -> str:
    return "".join(f"\n{cause}: {n}" for cause, n in causes.items())


def _box(ax: Axes, x: float, y: float, text: str, colour: str) -> Text:
    return ax.text(
        x,
        y,
        text,
        ha="center",
        va="center",
        fontsize=9.5,
        linespacing=1.35,
        bbox={
            "boxstyle": "round,pad=0.55",
            "facecolor": "white",
            "edgecolor": colour,
            "linewidth": 1.8,
        },
    )


def _patch(text: Text) -> FancyBboxPatch:
    patch = text.get_bbox_patch()
    assert patch is not None  # every box is drawn with a bbox
    return patch


def _down(ax: Axes, upper: Text, lower: Text, x: float = 0.5) -> None:
    """An arrow from the bottom of ``upper`` to the top of ``lower`` (at x in ``lower``)."""
    ax.annotate(
        "",
        xy=(x, 1),
        xycoords=_patch(lower),
        xytext=(0.5, 0),
        textcoords=_patch(upper),
        arrowprops=ARROW,
    )


def _aside(ax: Axes, y: float, side: Text) -> None:
    """An arrow from the main column at height ``y`` to the left edge of ``side``."""
    ax.annotate(
        "",
        xy=(0, 0.5),
        xycoords=_patch(side),
        xytext=(MAIN_X, y),
        textcoords="data",
        arrowprops=ARROW,
    )


def draw_flow(counts: DispositionCounts) -> bytes:
    c = counts
    with figure(8.4, 6.0) as fig:
        ax = fig.add_subplot()
        ax.set_axis_off()
        ax.set_xlim(0, 1)
        ax.set_ylim(0, 1)
        raw = _box(ax, MAIN_X, 0.94, f"Raw trials\nn = {c.raw}", ACCENT)
        complete = _box(
            ax,
            MAIN_X,
            0.66,
            f"Complete trials\nn = {c.complete}\n"
            f"{c.complete_successes} successes, {c.complete_timeouts} timeouts"
            + (f", {c.complete_failures} failed" if c.complete_failures else ""),
            ACCENT,
        )
        valid = _box(ax, MAIN_X, 0.27, f"Valid trials\nn = {c.valid}", ACCENT)
        _down(ax, raw, complete)
        _down(ax, complete, valid)
        incomplete = _box(
            ax,
            SIDE_X,
            0.81,
            f"Excluded as incomplete\nn = {c.incomplete}{_causes(c.incomplete_causes)}",
            EXCLUDED,
        )
        _aside(ax, 0.81, incomplete)
        low = _box(
            ax,
            SIDE_X,
            0.52,
            "Successes excluded as low quality\n"
            f"n = {c.excluded_low_quality}{_causes(c.low_quality_causes)}",
            LOW_QUALITY,
        )
        _aside(ax, 0.52, low)
        review = _box(
            ax,
            SIDE_X,
            0.38,
            f"Reviewer decisions\nexcluded: {c.excluded_by_reviewer}\n"
            f"included against a rule: {c.included_by_reviewer}",
            REVIEWER,
        )
        _aside(ax, 0.38, review)
        flagged = f"\n{c.marked_successes} flagged, marked" if c.marked_successes else ""
        successes = _box(ax, 0.1, 0.07, f"Successes\nn = {c.valid_successes}{flagged}", SUCCESS)
        timeouts = _box(ax, 0.47, 0.07, failures_text(c), TIMEOUT)
        _down(ax, valid, successes)
        _down(ax, valid, timeouts)
        return png(fig)


def failures_text(c: DispositionCounts) -> str:
    """The valid non-successes: timeouts, and the trials a task's judge ended ``failed``
    when there are any."""
    if not c.valid_failures:
        return (
            f"Timeouts, kept as valid failures\nn = {c.valid_timeouts}\n"
            f"{c.marked_timeouts} flagged, kept and marked"
        )
    marked = c.marked_timeouts + c.marked_failures
    return (
        f"Timeouts and failures, kept as valid\nn = {c.valid_timeouts} timeouts, "
        f"{c.valid_failures} failed\n{marked} flagged, kept and marked"
    )

"""A figure on its own Agg canvas, its style, and its PNG bytes."""

from __future__ import annotations

import io
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, cast

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

DPI = 110
SUCCESS = "#2e7d32"
TIMEOUT = "#e07b00"
FAILED = "#8d4e00"
EXCLUDED = "#9e9e9e"
LOW_QUALITY = "#c62828"
REVIEWER = "#6a1b9a"
ACCENT = "#1565c0"

STYLE = {
    "font.size": 9.5,
    "axes.titlesize": 10.5,
    "axes.titleweight": "bold",
    "axes.labelsize": 9.5,
    "axes.spines.top": False,
    "axes.spines.right": False,
    "axes.grid": True,
    "grid.alpha": 0.3,
    "legend.fontsize": 8.5,
    "legend.frameon": False,
    "axes.formatter.useoffset": False,
}


@dataclass(frozen=True)
class RenderedFigure:
    """One figure of the report: an anchor ``key``, a title, a caption and PNG bytes."""

    key: str
    title: str
    caption: str
    png: bytes


@contextmanager
def figure(width_in: float, height_in: float) -> Iterator[Figure]:
    """A new figure on an Agg canvas, drawn under the report's style."""
    import matplotlib as mpl  # noqa: PLC0415
    from matplotlib.backends.backend_agg import FigureCanvasAgg  # noqa: PLC0415
    from matplotlib.figure import Figure  # noqa: PLC0415

    with mpl.rc_context(cast(Any, STYLE)):
        fig = Figure(figsize=(width_in, height_in), dpi=DPI, layout="constrained")
        FigureCanvasAgg(fig)
        yield fig


def png(fig: Figure) -> bytes:
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", dpi=DPI, facecolor="white", metadata={"Software": None})
    return buffer.getvalue()


def marker_size(count: int) -> float:
    """Scatter marker area: smaller as points crowd."""
    return 16.0 if count <= 100 else 9.0 if count <= 400 else 5.0


def empty(ax: Axes, message: str) -> None:
    """Mark an axes that has nothing to draw."""
    ax.set_axis_off()
    ax.text(0.5, 0.5, message, ha="center", va="center", transform=ax.transAxes, color="0.4")

"""The report's figures, drawn with matplotlib's Agg canvas (no pyplot, no global backend):
each module draws one figure from an :class:`~workcell.audit.run.AuditResult` and returns
it as PNG bytes."""

from __future__ import annotations

from workcell.audit.figures.canvas import RenderedFigure
from workcell.audit.figures.render import render_figures

__all__ = ["RenderedFigure", "render_figures"]

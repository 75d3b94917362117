"""Small HTML building blocks for the report: escaped text, tables, numbers."""

from __future__ import annotations

import base64
import html
import math
from collections.abc import Iterable, Sequence

from workcell.metrics import Descriptive

DASH = "\u2013"
"""Shown for an undefined value."""


def esc(value: object) -> str:
    return html.escape(str(value), quote=True)


def number(value: float | int | None, digits: int = 3) -> str:
    """A number for a table: '-' when undefined, ``digits`` significant decimals."""
    if value is None or (isinstance(value, float) and not math.isfinite(value)):
        return DASH
    if isinstance(value, int):
        return str(value)
    magnitude = abs(value)
    if magnitude != 0 and (magnitude < 1e-2 or magnitude >= 1e6):
        return f"{value:.{digits}e}"
    return f"{value:.{digits}f}"


def mean_sd(d: Descriptive, scale: float = 1.0, digits: int = 3) -> str:
    return f"{number(d.mean * scale, digits)} ± {number(d.sd * scale, digits)}"


def median_iqr(d: Descriptive, scale: float = 1.0, digits: int = 3) -> str:
    return (
        f"{number(d.median * scale, digits)} "
        f"[{number(d.q1 * scale, digits)}, {number(d.q3 * scale, digits)}]"
    )


def table(header: Sequence[str], rows: Iterable[Sequence[object]], css: str = "") -> str:
    """A table of escaped cells (pass pre-built HTML by wrapping it in :class:`Raw`)."""
    head = "".join(f"<th>{esc(h)}</th>" for h in header)
    body = "".join(
        "<tr>"
        + "".join(f"<td>{cell if isinstance(cell, Raw) else esc(cell)}</td>" for cell in row)
        + "</tr>"
        for row in rows
    )
    cls = f' class="{css}"' if css else ""
    return f"<table{cls}><thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>"


class Raw(str):
    """Text that is already HTML (not escaped again by :func:`table`)."""


def image(png: bytes, alt: str) -> str:
    data = base64.b64encode(png).decode("ascii")
    return f'<img src="data:image/png;base64,{data}" alt="{esc(alt)}">'


CSS = """
body { font-family: system-ui, -apple-system, "Segoe UI", sans-serif; margin: 2rem auto;
       max-width: 70rem; padding: 0 1.2rem; color: #1d1d1f; line-height: 1.45; }
h1 { font-size: 1.6rem; margin-bottom: .2rem; }
h2 { font-size: 1.2rem; margin-top: 2.2rem; border-bottom: 1px solid #ddd; padding-bottom: .2rem; }
.meta { color: #555; font-size: .9rem; }
.key { display: flex; gap: 1rem; flex-wrap: wrap; margin: 1rem 0; }
.key div { border: 1px solid #ddd; border-radius: 8px; padding: .6rem 1rem; min-width: 9rem; }
.key b { display: block; font-size: 1.4rem; }
figure { margin: 1rem 0; }
figure img { max-width: 100%; border: 1px solid #eee; }
figcaption { color: #555; font-size: .9rem; }
table { border-collapse: collapse; margin: .6rem 0; font-size: .88rem; }
th, td { border-bottom: 1px solid #e4e4e4; padding: .25rem .6rem; text-align: left;
         vertical-align: top; }
th { background: #f6f6f6; }
table.long { display: block; max-height: 32rem; overflow: auto; }
.excluded { color: #8a8a8a; }
.reviewer { color: #6a1b9a; font-weight: 600; }
.flag { color: #c62828; }
code { font-size: .85rem; }
"""

"""The README's settings table, generated from the declarations, and the markers that
delimit it in the README (a test fails when the committed table drifts)."""

from __future__ import annotations

import json

from workcell.settings.validate import allowed_text
from workcell.settings.walk import leaf_settings

BEGIN = (
    "<!-- settings table: generated from the declarations by python -m workcell.session.readme -->"
)
END = "<!-- end of the settings table -->"


def _cell(text: str) -> str:
    return text.replace("|", "\\|")


def _default(value: object) -> str:
    if isinstance(value, float):
        return f"{value:.6g}"
    if isinstance(value, tuple):
        return "[" + ", ".join(_default(v) for v in value) + "]"
    return json.dumps(value) if isinstance(value, str) else str(value)


def markdown_table(cls: type) -> str:
    """Every setting of ``cls``: key, default, unit, allowed values and meaning."""
    lines = ["| setting | default | unit | allowed | meaning |", "|---|---|---|---|---|"]
    for d in leaf_settings(cls):
        cells = (
            f"`{d.key}`",
            f"`{_default(d.default)}`",
            d.spec.unit,
            allowed_text(d.spec, d.hint),
            d.spec.doc,
        )
        lines.append("| " + " | ".join(_cell(c) for c in cells) + " |")
    return "\n".join(lines) + "\n"


def replace_table(readme: str, table: str) -> str:
    """``readme`` with the text between :data:`BEGIN` and :data:`END` replaced by ``table``;
    ValueError when the markers are missing."""
    start, end = readme.find(BEGIN), readme.find(END)
    if start < 0 or end < start:
        raise ValueError(f"the README lacks the markers {BEGIN!r} ... {END!r}")
    return readme[: start + len(BEGIN)] + "\n" + table + readme[end:]

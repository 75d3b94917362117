"""Small validators that turn a bad value into one line naming field, value and what is allowed."""

from __future__ import annotations

import math
from collections.abc import Sequence


def _fmt(value: object) -> str:
    if isinstance(value, float):
        return f"{value:g}"
    if isinstance(value, tuple):
        return "(" + ", ".join(_fmt(v) for v in value) + ")"
    return repr(value)


def problem(field: str, value: object, allowed: str) -> str:
    """One problem line: ``field = value: allowed``."""
    return f"{field} = {_fmt(value)}: {allowed}"


def positive(field: str, value: float, unit: str = "") -> list[str]:
    if not math.isfinite(value) or value <= 0:
        return [problem(field, value, f"must be a finite number > 0{(' ' + unit) if unit else ''}")]
    return []


def in_range(field: str, value: float, low: float, high: float, unit: str = "") -> list[str]:
    if not math.isfinite(value) or not low <= value <= high:
        suffix = f" {unit}" if unit else ""
        return [problem(field, value, f"must be between {low:g} and {high:g}{suffix}")]
    return []


def one_of(field: str, value: object, allowed: Sequence[str]) -> list[str]:
    if value not in allowed:
        return [problem(field, value, "must be one of " + ", ".join(repr(a) for a in allowed))]
    return []


def length(field: str, values: Sequence[float], n: int) -> list[str]:
    if len(values) != n:
        return [problem(field, tuple(values), f"must have exactly {n} components")]
    return []

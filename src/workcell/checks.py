"""Small validators that turn a bad value into one line naming field, value and what is allowed."""

from __future__ import annotations

import math
from collections.abc import Sequence

from workcell.errors import Problem


def problem(field: str, value: object, allowed: str) -> Problem:
    """One problem line: ``field = value: allowed`` (its parts kept, see :class:`Problem`)."""
    return Problem(field, value, allowed)


def finite_number(value: object) -> bool:
    """An int or float a float can hold: not a bool, NaN, an infinity or a whole number too
    large to convert (which would raise OverflowError in the arithmetic that follows)."""
    if isinstance(value, bool) or not isinstance(value, int | float):
        return False
    try:
        return math.isfinite(value)
    except OverflowError:
        return False


def positive(field: str, value: float, unit: str = "") -> list[str]:
    if not finite_number(value) or value <= 0:
        return [problem(field, value, f"must be a finite number > 0{(' ' + unit) if unit else ''}")]
    return []


def in_range(field: str, value: float, low: float, high: float, unit: str = "") -> list[str]:
    if not finite_number(value) or not low <= value <= high:
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

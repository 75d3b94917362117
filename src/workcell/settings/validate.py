"""Validation generated from the declarations: one line per bad value, naming the setting,
the value and what is allowed, in the words the template and the README use."""

from __future__ import annotations

import dataclasses
import re
from typing import Any, Literal, get_args, get_origin

from workcell import checks
from workcell.settings.declare import Spec, spec_of
from workcell.settings.walk import type_hints


def _number(value: float) -> str:
    if value == 2**63 - 1:
        return "2^63-1"
    if isinstance(value, int):
        return str(value)
    return f"{value:g}"


def _suffix(unit: str) -> str:
    return "" if unit in ("", "1") else f" {unit}"


def _is_number(value: object) -> bool:
    return isinstance(value, int | float) and not isinstance(value, bool)


def bounds_text(spec: Spec, whole: bool) -> str:
    """What a number (or each component or item) may be, e.g. ``between 0.01 and 1 m/s``,
    ``> 0 and at most 3600 s``, ``a whole number from 1 to 20 boxes``."""
    low, high, unit = spec.low, spec.high, _suffix(spec.unit)
    if whole:
        if low is not None and high is not None:
            return f"a whole number from {_number(low)} to {_number(high)}{unit}"
        if low is not None:
            return f"a whole number >= {_number(low)}{unit}"
        return f"a whole number{unit}"
    if low is not None and high is not None:
        if spec.low_open:
            return f"> {_number(low)} and at most {_number(high)}{unit}"
        return f"between {_number(low)} and {_number(high)}{unit}"
    if low is not None:
        return f"a finite number {'>' if spec.low_open else '>='} {_number(low)}{unit}"
    return f"a finite number ({spec.unit})" if unit else "a finite number"


def allowed_text(spec: Spec, hint: Any) -> str:
    """Everything a setting allows, in words (without the ``must be``)."""
    origin = get_origin(hint)
    if origin is Literal:
        text = "one of " + ", ".join(repr(a) for a in get_args(hint))
    elif hint is str:
        text = spec.pattern_doc or "text"
    elif origin is tuple:
        item = get_args(hint)[0]
        each = bounds_text(spec, item is int)
        if spec.length is not None:
            text = f"{spec.length} components, each {each}"
        else:
            text = f"a list of {spec.min_items or 0} or more items, each {each}"
    else:
        text = bounds_text(spec, hint is int)
    return f"{text}; {spec.constraint}" if spec.constraint else text


def described(spec: Spec, hint: Any) -> str:
    """A setting's documentation with what it allows: ``belt speed (between 0.01 and 1
    m/s)``; the TOML template's comment and the setup page's text."""
    return f"{spec.doc} ({allowed_text(spec, hint)})"


def _admits(spec: Spec, value: object, whole: bool) -> bool:
    if whole:
        if type(value) is not int:
            return False
    elif not checks.finite_number(value):
        return False
    number: float = value  # type: ignore[assignment]
    if spec.low is not None and (number <= spec.low if spec.low_open else number < spec.low):
        return False
    return spec.high is None or number <= spec.high


def check_value(key: str, value: object, spec: Spec, hint: Any) -> list[str]:
    """The problems of one value of the setting ``key`` (none when it is allowed)."""
    if hint is float or hint is int:
        if _admits(spec, value, hint is int):
            return []
        return [checks.problem(key, value, f"must be {bounds_text(spec, hint is int)}")]
    origin = get_origin(hint)
    if origin is Literal:
        return checks.one_of(key, value, tuple(str(a) for a in get_args(hint)))
    if hint is str:
        ok = isinstance(value, str) and (spec.pattern is None or re.fullmatch(spec.pattern, value))
        return [] if ok else [checks.problem(key, value, f"must be {allowed_text(spec, hint)}")]
    if origin is tuple:
        return _check_tuple(key, value, spec, get_args(hint)[0] is int)
    return []


def _check_tuple(key: str, value: object, spec: Spec, whole: bool) -> list[str]:
    items = tuple(value) if isinstance(value, tuple | list) else ()
    if spec.length is not None:
        if len(items) != spec.length:
            return checks.length(key, items, spec.length)
        if all(_admits(spec, v, whole) for v in items):
            return []
        return [checks.problem(key, items, f"every component must be {bounds_text(spec, whole)}")]
    if len(items) < (spec.min_items or 0):
        noun = "item" if spec.min_items == 1 else "items"
        return [checks.problem(key, items, f"must list at least {spec.min_items} {noun}")]
    return [
        checks.problem(f"{key}[{i}]", v, f"must be {bounds_text(spec, whole)}")
        for i, v in enumerate(items)
        if not _admits(spec, v, whole)
    ]


_DECLARED: dict[type, tuple[tuple[str, Spec, Any], ...]] = {}


def _declared_fields(cls: type) -> tuple[tuple[str, Spec, Any], ...]:
    """``(name, spec, type)`` of every declared setting of ``cls`` (cached per class:
    configurations are validated on every construction)."""
    found = _DECLARED.get(cls)
    if found is None:
        hints = type_hints(cls)
        found = tuple(
            (f.name, spec, hints[f.name])
            for f in dataclasses.fields(cls)
            if (spec := spec_of(f)) is not None
        )
        _DECLARED[cls] = found
    return found


def check_as(cls: type, name: str, key: str, value: object) -> list[str]:
    """``value`` checked against the declaration of the setting ``name`` of ``cls``, its
    problems naming ``key`` (e.g. the command-line flag that sets it)."""
    for declared, spec, hint in _declared_fields(cls):
        if declared == name:
            return check_value(key, value, spec, hint)
    raise TypeError(f"{cls.__name__}.{name} is not declared with setting()")


def declared_problems(config: object, prefix: str) -> list[str]:
    """Every declared setting of the dataclass ``config`` checked against its declaration;
    problems name a setting ``prefix.name`` (``prefix`` is the section the class fills,
    ``""`` at the top). Sections are skipped: they validate themselves."""
    problems: list[str] = []
    for name, spec, hint in _declared_fields(type(config)):
        key = f"{prefix}.{name}" if prefix else name
        problems += check_value(key, getattr(config, name), spec, hint)
    return problems

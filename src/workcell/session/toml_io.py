"""Configuration dataclasses to and from TOML, with every problem reported at once.

Loading is strict: an unknown key (a typo) is an error naming the key and the keys that
section knows, never silently ignored. The commented template that writes a configuration
back out is :mod:`workcell.settings.template`.
"""

from __future__ import annotations

import dataclasses
import json
import tomllib
import types
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any, Literal, TypeVar, Union, get_args, get_origin, get_type_hints

from workcell.errors import ConfigError, Problem

T = TypeVar("T")
_MISSING = object()


def load_toml(path: Path) -> dict[str, Any]:
    """Read a TOML file; a missing or malformed file is a one-line ConfigError."""
    try:
        with Path(path).open("rb") as handle:
            return tomllib.load(handle)
    except FileNotFoundError:
        raise ConfigError([f"config file {str(path)!r} does not exist"]) from None
    except tomllib.TOMLDecodeError as error:
        raise ConfigError([f"config file {str(path)!r} is not valid TOML: {error}"]) from None
    except OSError as error:
        raise ConfigError([f"config file {str(path)!r} cannot be read: {error}"]) from None


def apply_overrides(data: Mapping[str, Any], overrides: Sequence[str]) -> dict[str, Any]:
    """``data`` with ``key.path=value`` overrides applied; values parse as TOML, else text."""
    merged: dict[str, Any] = json.loads(json.dumps(data))
    problems = []
    for override in overrides:
        key, sep, text = override.partition("=")
        parts = key.strip().split(".")
        if not sep or not all(parts):
            problems.append(f"--set {override!r}: must be KEY=VALUE, e.g. task.rounds=3")
            continue
        try:
            value = tomllib.loads(f"v = {text.strip()}")["v"]
        except tomllib.TOMLDecodeError:
            value = text.strip()
        table = merged
        for part in parts[:-1]:
            nested = table.setdefault(part, {})
            if not isinstance(nested, dict):
                problems.append(f"--set {override!r}: {part!r} is a value, not a section")
                break
            table = nested
        else:
            table[parts[-1]] = value
    if problems:
        raise ConfigError(problems)
    return merged


def from_mapping(cls: type[T], data: Mapping[str, Any], path: str = "") -> T:
    """Build dataclass ``cls`` from ``data``; ``path`` prefixes problems (``"world."``)."""
    problems: list[str] = []
    hints = get_type_hints(cls)
    fields = {f.name: f for f in dataclasses.fields(cls)}  # type: ignore[arg-type]
    for key in data:
        if key not in fields:
            allowed = f"unknown setting; allowed here: {', '.join(fields)}"
            problems.append(Problem(f"{path}{key}", data[key], allowed, f"{path}{key}: {allowed}"))
    kwargs: dict[str, Any] = {}
    for name in fields:
        value = data.get(name, _MISSING)
        if value is _MISSING:
            continue
        kind = hints[name]
        if dataclasses.is_dataclass(kind):
            if not isinstance(value, Mapping):
                allowed = f"must be a [{path}{name}] section"
                problems.append(
                    Problem(path + name, value, allowed, f"{path}{name} = {value!r}: {allowed}")
                )
                continue
            try:
                kwargs[name] = from_mapping(kind, value, f"{path}{name}.")  # type: ignore[arg-type]
            except ConfigError as error:
                problems += error.problems  # the section's default stands in below
            continue
        converted, problem = _convert(value, kind)
        if problem:
            problems.append(
                Problem(path + name, value, problem, f"{path}{name} = {value!r}: {problem}")
            )
        else:
            kwargs[name] = converted
    # Build even when something above failed, so that every problem is reported at once.
    parent = path.rsplit(".", 2)[0] + "." if path.count(".") > 1 else ""
    try:
        built = cls(**kwargs)
    except ConfigError as error:
        problems += [
            p.under(parent) if isinstance(p, Problem) else parent + p for p in error.problems
        ]
    if problems:
        raise ConfigError(problems)
    return built


def _convert(value: Any, kind: Any) -> tuple[Any, str]:
    """``value`` as ``kind``, or a problem text saying what is allowed."""
    origin = get_origin(kind)
    if origin is Literal:
        return value, "" if isinstance(value, str) else "must be text"
    if origin in (Union, types.UnionType):
        return value, ""
    if origin is tuple:
        if not isinstance(value, list | tuple):
            return value, "must be a list, e.g. [1, 2, 3]"
        inner = get_args(kind)[0]
        items = [_convert(v, inner) for v in value]
        bad = [p for _, p in items if p]
        return (
            (tuple(v for v, _ in items), f"every item {bad[0]}")
            if bad
            else (
                tuple(v for v, _ in items),
                "",
            )
        )
    if kind is bool:
        return value, "" if isinstance(value, bool) else "must be true or false"
    if kind is int:
        ok = isinstance(value, int) and not isinstance(value, bool)
        return value, "" if ok else "must be a whole number"
    if kind is float:
        ok = isinstance(value, int | float) and not isinstance(value, bool)
        return (float(value), "") if ok else (value, "must be a number")
    if kind is str:
        return value, "" if isinstance(value, str) else "must be text in quotes"
    return value, ""

"""Configuration dataclasses to and from TOML, with every problem reported at once.

Loading is strict: an unknown key (a typo) is an error naming the key and the keys that
section knows, never silently ignored. The commented template that writes a configuration
back out is :mod:`workcell.settings.template`.
"""

from __future__ import annotations

import dataclasses
import re
import sys
import tomllib
import types
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any, Literal, TypeVar, Union, get_args, get_origin, get_type_hints

from workcell.errors import ConfigError, Problem, cut, shown

T = TypeVar("T")
_MISSING = object()


def load_toml(path: Path, what: str = "config file") -> dict[str, Any]:
    """Read a TOML file; a missing, unreadable or malformed file is a one-line ConfigError
    naming it as ``what`` (``"study file"``)."""
    name = f"{what} {str(path)!r}"
    try:
        raw = Path(path).read_bytes()
    except FileNotFoundError:
        raise ConfigError([f"{name} does not exist"]) from None
    except OSError as error:
        raise ConfigError([f"{name} cannot be read: {error.strerror or error}"]) from None
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as error:
        byte = f"byte 0x{raw[error.start]:02x} at offset {error.start}"
        raise ConfigError([f"{name} is not UTF-8 text: {byte}"]) from None
    try:
        return parse_toml(text)
    except TomlTextError as error:
        raise ConfigError([f"{name} is not valid TOML: {error}"]) from None


class TomlTextError(ValueError):
    """TOML text Python cannot read; the message says why in one line."""


TOO_MANY_DIGITS = (
    f"a whole number of more than {sys.get_int_max_str_digits()} digits; no setting allows "
    f"one of more than 19"
)
TOO_DEEP = "lists or tables nested too deeply; no setting nests them"


def parse_toml(text: str) -> dict[str, Any]:
    """``text`` as TOML; :class:`TomlTextError` when it is not TOML, or when Python refuses
    it (a whole number too long to convert, lists nested deeper than its recursion limit)."""
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as error:
        raise TomlTextError(str(error)) from None
    except ValueError:  # the only other: int() refuses a number this long
        raise TomlTextError(_where(text, _long_number) + TOO_MANY_DIGITS) from None
    except RecursionError:
        raise TomlTextError(_where(text, _nesting) + TOO_DEEP) from None


def _long_number(line: str) -> bool:
    return re.search(f"[0-9_]{{{sys.get_int_max_str_digits() + 1}}}", line) is not None


def _nesting(line: str) -> bool:
    return line.count("[") + line.count("{") > 400


def _where(text: str, found: Callable[[str], bool]) -> str:
    """``line 2, world.box.mass: ``, the first line ``found`` and its key ("" if none)."""
    table = ""
    for number, line in enumerate(text.splitlines(), start=1):
        stripped = line.strip()
        if stripped.startswith("[") and "=" not in stripped.split("]")[0]:
            table = stripped.strip("[] ")
        if found(line):
            key = line.partition("=")[0].strip()
            return f"line {number}, {(f'{table}.{key}' if table else key)[:80]}: "
    return ""


def apply_overrides(data: Mapping[str, Any], overrides: Sequence[str]) -> dict[str, Any]:
    """``data`` with ``key.path=value`` overrides applied; values parse as TOML, else text."""
    merged = _tables_copied(data)
    problems = []
    for override in overrides:
        key, sep, text = override.partition("=")
        parts = key.strip().split(".")
        if not sep or not all(parts):
            problems.append(f"--set {shown(override)}: must be KEY=VALUE, e.g. task.rounds=3")
            continue
        try:
            value = tomllib.loads(f"v = {text.strip()}")["v"]
        except tomllib.TOMLDecodeError:
            value = text.strip()
        except ValueError:  # the only other: int() refuses a number this long
            problems.append(f"--set {shown(override)}: {TOO_MANY_DIGITS}")
            continue
        except RecursionError:
            problems.append(f"--set {shown(override)}: {TOO_DEEP}")
            continue
        table = merged
        for part in parts[:-1]:
            nested = table.setdefault(part, {})
            if not isinstance(nested, dict):
                problems.append(f"--set {shown(override)}: {shown(part)} is a value, not a section")
                break
            table = nested
        else:
            table[parts[-1]] = value
    if problems:
        raise ConfigError(problems)
    return merged


def _tables_copied(data: Mapping[str, Any]) -> dict[str, Any]:
    """``data`` with every table copied (overrides change those), values shared."""
    return {k: _tables_copied(v) if isinstance(v, Mapping) else v for k, v in data.items()}


def from_mapping(cls: type[T], data: Mapping[str, Any], path: str = "") -> T:
    """Build dataclass ``cls`` from ``data``; ``path`` prefixes problems (``"world."``)."""
    problems: list[str] = []
    hints = get_type_hints(cls)
    fields = {f.name: f for f in dataclasses.fields(cls)}  # type: ignore[arg-type]
    for key in data:
        if key not in fields:
            allowed = f"unknown setting; allowed here: {', '.join(fields)}"
            where = cut(f"{path}{key}")
            problems.append(Problem(f"{path}{key}", data[key], allowed, f"{where}: {allowed}"))
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
                    Problem(
                        path + name, value, allowed, f"{path}{name} = {shown(value)}: {allowed}"
                    )
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
                Problem(path + name, value, problem, f"{path}{name} = {shown(value)}: {problem}")
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
        if not isinstance(value, int | float) or isinstance(value, bool):
            return value, "must be a number"
        try:
            return float(value), ""
        except OverflowError:  # a whole number beyond a float: its declaration refuses it
            return value, ""
    if kind is str:
        return value, "" if isinstance(value, str) else "must be text in quotes"
    return value, ""

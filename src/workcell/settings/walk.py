"""Every setting and section of a configuration dataclass, in declaration order, with its
dotted key as the TOML file spells it (``world.box.mass``)."""

from __future__ import annotations

import dataclasses
from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any, Literal, get_args, get_origin, get_type_hints

from workcell.settings.declare import Spec, field_doc, spec_of


@dataclass(frozen=True)
class Declared:
    """One leaf setting: its key, Python type, default and :class:`Spec`."""

    key: str
    name: str
    hint: Any
    default: object
    spec: Spec

    @property
    def choices(self) -> tuple[str, ...] | None:
        """A ``Literal`` setting's allowed values."""
        if get_origin(self.hint) is Literal:
            return tuple(str(a) for a in get_args(self.hint))
        return None


@dataclass(frozen=True)
class Section:
    """A nested configuration dataclass: its key and documentation."""

    key: str
    doc: str


_HINTS: dict[type, dict[str, Any]] = {}


def type_hints(cls: type) -> dict[str, Any]:
    """``cls``'s resolved field types (cached: validation asks on every construction)."""
    hints = _HINTS.get(cls)
    if hints is None:
        hints = _HINTS[cls] = get_type_hints(cls)
    return hints


def leaf_settings(cls: type, prefix: str = "") -> Iterator[Declared]:
    """Every setting of ``cls`` and of its sections, depth first in declaration order."""
    for item in walk(cls, prefix):
        if isinstance(item, Declared):
            yield item


def walk(cls: type, prefix: str = "") -> Iterator[Declared | Section]:
    """Settings and sections of ``cls`` in declaration order; a section comes before its
    settings. A field declared without :func:`~workcell.settings.declare.setting` is an
    error: every setting must say its unit and what it allows."""
    hints = type_hints(cls)
    defaults = cls()
    for field in dataclasses.fields(cls):
        key, hint = f"{prefix}{field.name}", hints[field.name]
        if dataclasses.is_dataclass(hint):
            yield Section(key, field_doc(field))
            yield from walk(hint, f"{key}.")  # type: ignore[arg-type]
            continue
        spec = spec_of(field)
        if spec is None:
            raise TypeError(f"{cls.__name__}.{field.name} is not declared with setting()")
        yield Declared(key, field.name, hint, getattr(defaults, field.name), spec)

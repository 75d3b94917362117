"""Declaring a setting once: its default, unit, allowed values and documentation.

Every field of a configuration dataclass is declared with :func:`setting` (or
:func:`section` for a nested dataclass). The declaration is the single source of the
field's validation (:mod:`workcell.settings.validate`), its line in the commented TOML
template (:mod:`workcell.settings.template`), the setup page's form hint and the README's
settings table (:mod:`workcell.settings.table`). Rules that tie several fields together
(a rate that must divide another) stay in the class's ``__post_init__``; ``constraint``
says them in words so the template, the page and the README show them too.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, TypeVar

T = TypeVar("T")

SPEC = "workcell.setting"
"""The metadata key of a field's :class:`Spec`."""

DOC = "doc"
"""The metadata key of a section's documentation."""


@dataclass(frozen=True)
class Spec:
    """What a setting is and what it allows, besides its default and its type.

    ``unit`` is the SI unit (``m/s``, ``rad``, ``Hz``), a count noun (``boxes``) or ``1``
    for a dimensionless number; empty only for a choice or text. ``low`` / ``high`` bound
    a number, a vector's every component or a list's every item (``low_open``: ``low``
    itself is not allowed). A tuple setting is either a vector of exactly ``length``
    components, checked as one value, or a list of at least ``min_items`` items, each
    checked on its own (its problems name ``key[i]``). Text must match ``pattern``
    entirely; ``pattern_doc`` says what that allows in words.
    """

    doc: str
    unit: str = ""
    low: float | None = None
    high: float | None = None
    low_open: bool = False
    length: int | None = None
    min_items: int | None = None
    pattern: str | None = None
    pattern_doc: str = ""
    constraint: str = ""


def setting(
    default: T,
    doc: str,
    *,
    unit: str = "",
    low: float | None = None,
    high: float | None = None,
    low_open: bool = False,
    length: int | None = None,
    min_items: int | None = None,
    pattern: str | None = None,
    pattern_doc: str = "",
    constraint: str = "",
) -> T:
    """A field with its default, documentation (what it means, without unit or range),
    unit and allowed values; see :class:`Spec`."""
    spec = Spec(
        doc=doc,
        unit=unit,
        low=low,
        high=high,
        low_open=low_open,
        length=length,
        min_items=min_items,
        pattern=pattern,
        pattern_doc=pattern_doc,
        constraint=constraint,
    )
    field: T = dataclasses.field(default=default, metadata={SPEC: spec, DOC: doc})
    return field


def same_as(cls: type, name: str, doc: str = "") -> Any:
    """A field declared like the setting ``name`` of the configuration dataclass ``cls``:
    its default, unit and allowed values, so a configuration that takes a value over from
    another does not restate them. ``doc`` replaces the documentation when given."""
    fields = {f.name: f for f in dataclasses.fields(cls)}
    spec = spec_of(fields[name])
    if spec is None:
        raise TypeError(f"{cls.__name__}.{name} is not declared with setting()")
    spec = dataclasses.replace(spec, doc=doc or spec.doc)
    return dataclasses.field(default=fields[name].default, metadata={SPEC: spec, DOC: spec.doc})


def declared_default(cls: type, name: str) -> Any:
    """The default of the setting ``name`` of the configuration dataclass ``cls``."""
    fields = {f.name: f for f in dataclasses.fields(cls)}
    if name not in fields or spec_of(fields[name]) is None:
        raise TypeError(f"{cls.__name__}.{name} is not declared with setting()")
    return fields[name].default


def section(factory: Callable[[], T], doc: str) -> T:
    """A nested configuration dataclass and its documentation."""
    field: T = dataclasses.field(default_factory=factory, metadata={DOC: doc})
    return field


def spec_of(field: dataclasses.Field[Any]) -> Spec | None:
    """The :class:`Spec` of a field declared with :func:`setting` (None for a section)."""
    spec = field.metadata.get(SPEC)
    return spec if isinstance(spec, Spec) else None


def field_doc(field: dataclasses.Field[Any]) -> str:
    """The documentation of a field declared with :func:`setting` or :func:`section`."""
    return str(field.metadata.get(DOC, ""))

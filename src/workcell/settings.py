"""Declaring configuration fields with their documentation.

Every field of a configuration dataclass is declared with :func:`setting` (or
:func:`section` for a nested dataclass) so that its one-line documentation travels with it:
``workcell config --defaults`` prints it above each key, and the setup page shows it.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from typing import Any, TypeVar

T = TypeVar("T")

DOC = "doc"


def setting(default: T, doc: str) -> T:
    """A field with a default value and its documentation (say the unit and allowed range)."""
    field: T = dataclasses.field(default=default, metadata={DOC: doc})
    return field


def section(factory: Callable[[], T], doc: str) -> T:
    """A nested configuration dataclass and its documentation."""
    field: T = dataclasses.field(default_factory=factory, metadata={DOC: doc})
    return field


def field_doc(field: dataclasses.Field[Any]) -> str:
    """The documentation of a field declared with :func:`setting` or :func:`section`."""
    return str(field.metadata.get(DOC, ""))

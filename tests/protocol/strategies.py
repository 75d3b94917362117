"""Hypothesis strategies for protocol messages, derived from their type hints (and the
codec's documented ranges), so every message type is covered without listing fields."""

from __future__ import annotations

import dataclasses
import enum
import math
import types
from typing import Any, Literal, Union, get_args, get_origin, get_type_hints

from hypothesis import strategies as st

from workcell.protocol.scene import Pose
from workcell.protocol.validation import MAX_TEXT, POSITION_LIMIT_M, RANGES

finite = st.floats(allow_nan=False, allow_infinity=False)
json_scalars = st.none() | st.booleans() | st.integers(-(2**53), 2**53) | finite | st.text()
"""Scalars a valid message may carry in its free-form fields."""
json_values = st.recursive(
    json_scalars,
    lambda inner: (
        st.lists(inner, max_size=4) | st.dictionaries(st.text(max_size=8), inner, max_size=4)
    ),
    max_leaves=12,
)
huge_integers = st.builds(
    lambda digits, sign: sign * (10**digits + 7), st.integers(300, 4000), st.sampled_from((1, -1))
)
"""Integers JSON allows but no float holds: 301 to 4001 digits."""
lone_surrogates = st.builds(
    lambda before, surrogate, after: before + surrogate + after,
    st.text(max_size=3),
    st.sampled_from(("\ud800", "\udbff", "\udc00", "\udfff")),
    st.text(max_size=3),
)
"""Text JSON can carry (as an escape) but UTF-8 cannot: a lone UTF-16 surrogate."""
hostile_values = st.recursive(
    json_scalars | huge_integers | lone_surrogates,
    lambda inner: (
        st.lists(inner, max_size=4)
        | st.dictionaries(st.text(max_size=8) | lone_surrogates, inner, max_size=4)
    ),
    max_leaves=12,
)
"""Any JSON, valid in a message or not."""


def _unit(quat: tuple[float, float, float, float]) -> tuple[float, float, float, float]:
    norm = math.sqrt(sum(q * q for q in quat))
    w, x, y, z = (q / norm for q in quat)
    return (w, x, y, z)


quaternions = (
    st.tuples(*[st.floats(-1, 1)] * 4).filter(lambda q: sum(c * c for c in q) > 1e-3).map(_unit)
)
poses = st.tuples(*[st.floats(-POSITION_LIMIT_M, POSITION_LIMIT_M)] * 3, quaternions).map(
    lambda p: (p[0], p[1], p[2], *p[3])
)


def for_hint(hint: Any, bounds: tuple[float, float] | None = None, max_text: int = 64) -> Any:
    if hint == Pose:
        return poses
    if hint is bool:
        return st.booleans()
    if hint is int:
        low, high = bounds or (-(2**53 - 1), 2**53 - 1)
        return st.integers(int(low), int(high))
    if hint is float:
        if bounds:
            return st.floats(bounds[0], bounds[1])
        return finite
    if hint is str:
        return st.text(max_size=max_text)
    if hint is object:
        return json_values
    if isinstance(hint, type) and dataclasses.is_dataclass(hint):
        return for_message(hint)
    if isinstance(hint, type) and issubclass(hint, enum.Enum):
        return st.sampled_from(list(hint))
    origin, args = get_origin(hint), get_args(hint)
    if origin is Literal:
        return st.sampled_from(args)
    if origin in (Union, types.UnionType):
        return st.one_of(
            *(st.none() if a is type(None) else for_hint(a, bounds, max_text) for a in args)
        )
    if origin is tuple:
        if len(args) == 2 and args[1] is Ellipsis:
            return st.lists(for_hint(args[0], bounds), max_size=3).map(tuple)
        return st.tuples(*(for_hint(a, bounds) for a in args))
    if origin is dict:
        return st.dictionaries(st.text(max_size=8), for_hint(args[1]), max_size=4)
    raise TypeError(hint)


def for_message(cls: type) -> Any:
    hints = get_type_hints(cls)
    fields = {
        f.name: for_hint(hints[f.name], RANGES.get((cls, f.name)), MAX_TEXT.get((cls, f.name), 64))
        for f in dataclasses.fields(cls)
    }
    return st.builds(cls, **fields)

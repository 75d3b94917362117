"""Strict conversion of decoded JSON into protocol dataclasses, driven by their type hints.

Exact types (a bool is not a number, a number is not text), no unknown or missing fields
(fields with defaults may be left out), finite numbers only, documented ranges, unit
quaternions (within 1e-2, then normalised). Every problem is a :class:`ProtocolError`
naming the field by its dotted path (``input.left.grip``) and saying what is allowed; where
one field's value is the problem it also carries it as data (``problem``: path, value,
allowed), which the server sends in the ``Error`` message.
"""

from __future__ import annotations

import dataclasses
import enum
import functools
import math
import re
import types
from typing import Any, Literal, Union, get_args, get_origin, get_type_hints

from workcell.errors import WorkcellError
from workcell.protocol import messages as m
from workcell.protocol.messages import ErrorCode
from workcell.protocol.scene import Pose
from workcell.task.events import STOP_NOTE_MAX, TrialStarted

QUATERNION_TOLERANCE = 1e-2
"""How far from 1 a pose quaternion's norm may be before it is refused."""
POSITION_LIMIT_M = 100.0
"""A tracked position farther than this from the reference space origin is refused."""
MAX_SAFE_INTEGER = 2**53 - 1
"""The largest integer a browser represents exactly."""
INT64_MIN, INT64_MAX = -(2**63), 2**63 - 1
"""The integers free-form JSON may hold: what the encoder and the store write."""
MAX_NESTING = 64
"""How deep free-form JSON may nest (no setting nests more than a few levels; the encoder,
orjson, stops at 255, and every reply that echoes a value must be written)."""

RANGES: dict[tuple[type, str], tuple[float, float]] = {
    (m.ControllerState, "grip"): (0.0, 1.0),
    (m.ControllerState, "trigger"): (0.0, 1.0),
    (m.ControllerState, "stick"): (-1.0, 1.0),
    (m.ControllerState, "buttons"): (0, 255),
    (m.Input, "seq"): (0, MAX_SAFE_INTEGER),
    (m.FrameStats, "frames"): (0, 1_000_000),
    (m.FrameStats, "frame_ms_p50"): (0.0, 60_000.0),
    (m.FrameStats, "frame_ms_p95"): (0.0, 60_000.0),
    (m.FrameStats, "frame_ms_max"): (0.0, 60_000.0),
    (m.FrameStats, "draw_calls"): (0, 1_000_000),
    (m.FrameStats, "triangles"): (0, 1_000_000_000),
    (m.Ping, "rtt_ms"): (0.0, 3_600_000.0),
}
"""Inclusive bounds of numeric fields (each element, for tuples)."""
MAX_TEXT: dict[tuple[type, str], int] = {
    (m.Hello, "resume_token"): 128,
    (m.Hello, "seat"): 16,
    (m.Stop, "reason"): STOP_NOTE_MAX,
    (m.TakeOver, "reason"): STOP_NOTE_MAX,
    (m.HandBack, "reason"): STOP_NOTE_MAX,
}
"""Longest allowed text of a field (characters)."""
WIDE_INTEGERS: frozenset[tuple[type, str]] = frozenset({(TrialStarted, "trial_seed")})
"""Whole numbers the server sends that may exceed 2^53 (a 63-bit seed): a browser reads
them rounded and does not use them; a Python client reads them exactly."""


class ProtocolError(WorkcellError):
    """A message that is not valid protocol; ``code`` is an :class:`~messages.Error` code.
    ``problem`` holds the refused value as data when one field's value is the problem."""

    def __init__(
        self, code: ErrorCode, message: str, problem: m.FieldProblem | None = None
    ) -> None:
        self.code: ErrorCode = code
        self.problem = problem
        super().__init__(message)


def split_path(path: str) -> tuple[str | int, ...]:
    """``"input.left.stick[1]"`` as ``("input", "left", "stick", 1)``."""
    parts: list[str | int] = []
    for name, index in re.findall(r"([^.\[\]]+)|\[(\d+)\]", path):
        parts.append(int(index) if index else name)
    return tuple(parts)


def json_value(value: Any) -> object:
    """``value`` if every reader of the JSON holds it as it is (finite numbers, whole
    numbers within +-(2^53 - 1), text, lists and objects of them), else None."""
    if value is None or isinstance(value, bool | str):
        return value
    if isinstance(value, int):
        return value if abs(value) <= MAX_SAFE_INTEGER else None
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if isinstance(value, list | tuple):
        items = [json_value(item) for item in value]
        carried = all(i is not None or v is None for i, v in zip(items, value, strict=True))
        return items if carried else None
    if isinstance(value, dict) and all(isinstance(k, str) for k in value):
        return {k: json_value(v) for k, v in value.items()}
    return None


def field_problem(path: str, value: Any, allowed: str, message: str) -> m.FieldProblem:
    """A :class:`~messages.FieldProblem` for the value at dotted ``path``."""
    return m.FieldProblem(split_path(path), json_value(value), allowed, message)


def _invalid(code: ErrorCode, path: str, value: Any, allowed: str) -> ProtocolError:
    message = f"{path} = {_show(value)}: {allowed}"
    return ProtocolError(code, message, field_problem(path, value, allowed, message))


@functools.cache
def _hints(cls: type) -> dict[str, Any]:
    return get_type_hints(cls)


@functools.cache
def _fields(cls: type) -> tuple[dataclasses.Field[Any], ...]:
    return dataclasses.fields(cls)


def _show(value: Any) -> str:
    text = repr(value)
    return text if len(text) <= 40 else text[:37] + "..."


def build(cls: type, value: Any, path: str) -> Any:
    """``value`` (a decoded JSON object) as dataclass ``cls``; ``path`` names it."""
    if not isinstance(value, dict):
        raise _invalid("malformed", path, value, "must be an object")
    fields = _fields(cls)
    names = {f.name for f in fields}
    unknown = [key for key in value if key not in names]
    if unknown:
        raise ProtocolError(
            "malformed",
            f"{path}.{unknown[0]}: unknown field; allowed: {', '.join(sorted(names))}",
        )
    hints = _hints(cls)
    kwargs: dict[str, Any] = {}
    for f in fields:
        where = f"{path}.{f.name}"
        if f.name not in value:
            if f.default is dataclasses.MISSING and f.default_factory is dataclasses.MISSING:
                raise ProtocolError("malformed", f"{where}: missing; it is required")
            continue
        converted = (
            _wide_integer(value[f.name], where)
            if (cls, f.name) in WIDE_INTEGERS
            else convert(value[f.name], hints[f.name], where)
        )
        _check_range(cls, f.name, converted, where)
        kwargs[f.name] = converted
    return cls(**kwargs)


def _wide_integer(value: Any, path: str) -> int:
    if type(value) is not int:
        raise _invalid("malformed", path, value, "must be a whole number")
    return value


def convert(value: Any, hint: Any, path: str) -> Any:
    """``value`` as type ``hint`` or a ProtocolError saying what is allowed."""
    if hint is bool:
        if type(value) is not bool:
            raise _invalid("malformed", path, value, "must be true or false")
        return value
    if hint is int:
        if type(value) is not int:
            raise _invalid("malformed", path, value, "must be a whole number")
        if abs(value) > MAX_SAFE_INTEGER:
            raise _invalid("invalid_value", path, value, "must be within +-(2^53 - 1)")
        return value
    if hint is float:
        if type(value) not in (int, float):
            raise _invalid("malformed", path, value, "must be a number")
        return _finite_float(value, path)
    if hint is str:
        if not isinstance(value, str):
            raise _invalid("malformed", path, value, "must be text")
        return value
    if hint is object:
        _require_writable(value, path)
        return value
    if hint is type(None):
        if value is not None:
            raise _invalid("malformed", path, value, "must be null")
        return None
    if dataclasses.is_dataclass(hint):
        return build(hint, value, path)  # type: ignore[arg-type]
    if isinstance(hint, type) and issubclass(hint, enum.Enum):
        allowed = ", ".join(repr(member.value) for member in hint)
        for member in hint:
            if type(value) is type(member.value) and value == member.value:
                return member
        raise _invalid("malformed", path, value, f"must be one of {allowed}")
    origin, args = _shape(hint)
    if origin is Literal:
        if value not in args or type(value) is not type(args[0]):
            allowed = ", ".join(repr(a) for a in args)
            raise _invalid("malformed", path, value, f"must be one of {allowed}")
        return value
    if origin in (Union, types.UnionType):
        return _convert_union(value, args, path)
    if origin is tuple:
        converted = _convert_tuple(value, args, path)
        return _unit_pose(converted, path) if hint == Pose else converted
    if origin is dict:
        if not isinstance(value, dict):
            raise _invalid("malformed", path, value, "must be an object")
        return {key: convert(item, args[1], f"{path}.{key}") for key, item in value.items()}
    raise TypeError(f"{path}: no conversion for {hint!r}")  # a protocol author's mistake


def _finite_float(value: int | float, path: str) -> float:
    """``value`` as a finite float; an integer too large for a float (JSON allows any
    number of digits) is refused like infinity, never raised as OverflowError."""
    try:
        number = float(value)
    except OverflowError:
        number = math.inf
    if not math.isfinite(number):
        raise _invalid("invalid_value", path, value, "must be a finite number (within +-1.8e308)")
    return number


def _require_writable(value: Any, path: str, depth: int = 0) -> None:
    """Free-form JSON (settings, event fields) holds finite numbers only: no NaN or
    infinity, no integer beyond what a float holds, nor beyond 64 bits, and nests at most
    :data:`MAX_NESTING` deep (what the encoder, orjson, and the store write: a message
    that decodes must encode again, and so must a reply that names its values)."""
    if type(value) in (int, float):
        _finite_float(value, path)
    if type(value) is int and not INT64_MIN <= value <= INT64_MAX:
        raise _invalid("invalid_value", path, value, "must be within -2^63 to 2^63 - 1")
    if isinstance(value, list | dict) and depth >= MAX_NESTING:
        raise _invalid("malformed", path, "[...]", f"must nest at most {MAX_NESTING} levels deep")
    if isinstance(value, list):
        for i, item in enumerate(value):
            _require_writable(item, f"{path}[{i}]", depth + 1)
    elif isinstance(value, dict):
        for key, item in value.items():
            _require_writable(item, f"{path}.{key}", depth + 1)


def _convert_union(value: Any, args: tuple[Any, ...], path: str) -> Any:
    if value is None:
        if type(None) in args:
            return None
        raise ProtocolError("malformed", f"{path}: must not be null")
    options = [a for a in args if a is not type(None)]
    if len(options) == 1:
        return convert(value, options[0], path)
    for option in options:  # several non-null arms: the first that fits
        try:
            return convert(value, option, path)
        except ProtocolError:
            continue
    raise _invalid("malformed", path, value, "has none of the allowed types")


@functools.cache
def _shape(hint: Any) -> tuple[Any, tuple[Any, ...]]:
    """A type hint's origin and arguments (``typing.get_origin``/``get_args``), looked up
    once per hint: every message converts the same few hints."""
    return get_origin(hint), get_args(hint)


@functools.cache
def _all_floats(args: tuple[Any, ...]) -> bool:
    """Whether a fixed-length tuple hint holds floats only (poses, sticks)."""
    return all(arg is float for arg in args)


def _convert_tuple(value: Any, args: tuple[Any, ...], path: str) -> tuple[Any, ...]:
    if not isinstance(value, list):
        raise _invalid("malformed", path, value, "must be a list")
    if (
        _all_floats(args)
        and len(value) == len(args)
        and all(type(item) is float and math.isfinite(item) for item in value)
    ):
        return tuple(value)  # the common case, at once; anything else item by item below
    if len(args) == 2 and args[1] is Ellipsis:
        return tuple(convert(item, args[0], f"{path}[{i}]") for i, item in enumerate(value))
    if len(value) != len(args):
        raise ProtocolError(
            "malformed", f"{path}: must be a list of {len(args)} items, got {len(value)}"
        )
    pairs = enumerate(zip(value, args, strict=True))
    return tuple(convert(item, kind, f"{path}[{i}]") for i, (item, kind) in pairs)


def _unit_pose(pose: tuple[float, ...], path: str) -> tuple[float, ...]:
    """A pose with its position bounded and its quaternion unit (normalised)."""
    if any(abs(p) > POSITION_LIMIT_M for p in pose[:3]):
        raise ProtocolError(
            "invalid_value",
            f"{path} position = {pose[:3]}: must be within {POSITION_LIMIT_M:g} m of the origin",
        )
    quat = pose[3:]
    norm = math.sqrt(sum(q * q for q in quat))
    if abs(norm - 1.0) > QUATERNION_TOLERANCE:
        raise ProtocolError(
            "invalid_value",
            f"{path} quaternion = {quat}: must be a unit quaternion (w, x, y, z) within "
            f"{QUATERNION_TOLERANCE:g}; its norm is {norm:.6g}",
        )
    if abs(norm - 1.0) > 1e-12:
        return (*pose[:3], *(q / norm for q in quat))
    return pose


def _check_range(cls: type, name: str, value: Any, path: str) -> None:
    limit = MAX_TEXT.get((cls, name))
    if limit is not None and isinstance(value, str) and len(value) > limit:
        raise ProtocolError("invalid_value", f"{path}: must be at most {limit} characters")
    bounds = RANGES.get((cls, name))
    if bounds is None:
        return
    low, high = bounds
    items = value if isinstance(value, tuple) else (value,)
    for item in items:
        if item is not None and not low <= item <= high:  # None: an optional field unset
            raise _invalid("invalid_value", path, value, f"must be from {low:g} to {high:g}")

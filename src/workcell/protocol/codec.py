"""JSON text to and from protocol messages.

:func:`decode_client` is the only way the server reads a browser's message: it returns a
valid :data:`~workcell.protocol.messages.ClientMessage` or raises :class:`ProtocolError`
(never another exception), whatever the bytes. :func:`encode` writes compact JSON.
"""

from __future__ import annotations

import dataclasses
import enum
import functools
import json
import math
import re
from typing import Any

import orjson

from workcell.protocol import messages as m
from workcell.protocol.input_decode import quick_input
from workcell.protocol.validation import ProtocolError, build
from workcell.task.events import TASK_EVENTS

MAX_MESSAGE_BYTES = 64 * 1024
"""The largest message a client may send."""

__all__ = [
    "LONE_SURROGATE",
    "MAX_MESSAGE_BYTES",
    "ProtocolError",
    "decode_client",
    "decode_server",
    "encode",
    "has_utf8_form",
]


def _default(cls: type, name: str) -> Any:
    return next(f.default for f in dataclasses.fields(cls) if f.name == name)


def _key(cls: type) -> str:
    """What names a message class: its ``type``; ``event:<kind>`` for a task event."""
    kind = _default(cls, "type")
    return f"{kind}:{_default(cls, 'kind')}" if cls in TASK_EVENTS else str(kind)


def _by_type(classes: tuple[type, ...]) -> dict[str, type]:
    return {_key(cls): cls for cls in classes}


_CLIENT = _by_type(m.CLIENT_MESSAGES)
_SERVER = _by_type(m.SERVER_MESSAGES)


def _loads(text: str | bytes) -> Any:
    size = len(text) if isinstance(text, bytes) else len(text.encode("utf-8", "replace"))
    if size > MAX_MESSAGE_BYTES:
        raise ProtocolError(
            "too_large", f"message of {size} bytes: at most {MAX_MESSAGE_BYTES} are allowed"
        )
    if isinstance(text, bytes):
        try:
            text = text.decode("utf-8")
        except UnicodeDecodeError:
            raise ProtocolError("malformed", "message is not UTF-8 text") from None
    try:
        data = json.loads(text)  # NaN and Infinity are refused where they land
    except json.JSONDecodeError as error:
        raise ProtocolError("malformed", f"message is not JSON: {error.msg}") from None
    except (RecursionError, ValueError) as error:  # too deep, or an integer too long
        raise ProtocolError("malformed", f"message is not usable JSON: {error}") from None
    if _SURROGATE_ESCAPE.search(text) and not has_utf8_form(data):
        raise ProtocolError("malformed", LONE_SURROGATE)
    return data


_SURROGATE_ESCAPE = re.compile(r"\\u[dD][89a-fA-F]")
"""A JSON escape of a UTF-16 surrogate: a pair of them is one character, a lone one none."""
LONE_SURROGATE = (
    "message text holds a lone surrogate (an escape \\ud800 to \\udfff without its pair): "
    "text must be valid Unicode"
)


def has_utf8_form(value: Any) -> bool:
    """Every text in ``value`` (keys too) has a UTF-8 form: no lone surrogate, which the
    JSON decoder lets through and neither the encoder nor the store can write. Walked with
    a list, not recursion: JSON nested as deep as the decoder allows is walked too."""
    pending = [value]
    while pending:
        item = pending.pop()
        if isinstance(item, str):
            try:
                item.encode("utf-8")
            except UnicodeEncodeError:
                return False
        elif isinstance(item, list):
            pending.extend(item)
        elif isinstance(item, dict):
            pending.extend(item)
            pending.extend(item.values())
    return True


def _decode(text: str | bytes, known: dict[str, type]) -> Any:
    return _build(_loads(text), known)


def _build(data: Any, known: dict[str, type]) -> Any:
    if not isinstance(data, dict):
        raise ProtocolError("malformed", "message must be a JSON object with a 'type' field")
    kind = data.get("type")
    if kind == "event":
        kind = f"event:{data.get('kind')}"
    cls = known.get(kind) if isinstance(kind, str) else None
    if cls is None:
        allowed = ", ".join(sorted(known))
        raise ProtocolError("malformed", f"type = {str(kind)[:40]!r}: must be one of {allowed}")
    try:
        return build(cls, data, str(data["type"]))
    except RecursionError:
        raise ProtocolError("malformed", "message is nested too deeply") from None


def decode_client(text: str | bytes) -> m.ClientMessage:
    """A client message from its JSON text, strictly validated (an operator's Input, the
    message sent most, on a fast path first: :mod:`workcell.protocol.input_decode`)."""
    data = _loads(text)
    if isinstance(data, dict) and data.get("type") == "input":
        quick = quick_input(data)
        if quick is not None:
            return quick
    message: m.ClientMessage = _build(data, _CLIENT)
    return message


def decode_server(text: str | bytes) -> m.ServerMessage:
    """A server message from its JSON text (for clients written in Python and tests)."""
    message: m.ServerMessage = _decode(text, _SERVER)
    return message


_PLAIN = (str, int, bool, type(None))


@functools.cache
def _field_names(cls: type) -> tuple[str, ...]:
    return tuple(f.name for f in dataclasses.fields(cls))


def to_json_value(value: Any) -> Any:
    """Dataclasses as objects and tuples as lists, recursively (JSON-ready); a non-finite
    float becomes null (JSON has no NaN)."""
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if isinstance(value, _PLAIN):
        return value
    if isinstance(value, enum.Enum):
        return to_json_value(value.value)
    if isinstance(value, tuple | list):
        return [to_json_value(item) for item in value]
    if isinstance(value, dict):
        return {str(key): to_json_value(item) for key, item in value.items()}
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return {name: to_json_value(getattr(value, name)) for name in _field_names(type(value))}
    if hasattr(value, "item"):  # a numpy scalar
        return to_json_value(value.item())
    return value


_ORJSON_OPTIONS = orjson.OPT_NON_STR_KEYS | orjson.OPT_SERIALIZE_NUMPY


def encode(message: object) -> str:
    """Compact JSON text of a message (or of an API body): :func:`to_json_value`'s JSON.

    orjson writes it in one pass (dataclasses as objects in field order, tuples as lists,
    enums as their values, a non-finite float as null), calling :func:`_json_form` only for
    what it has no form of. The values are the json module's to the bit; the text differs
    only in form: non-ASCII characters as UTF-8 rather than escaped, and some floats in
    another of their shortest forms (``0.00001`` for ``1e-05``). A State is sent up
    to 100 times a second per session: orjson writes it about 10x faster (``bench/state.py``)."""
    return orjson.dumps(message, default=_json_form, option=_ORJSON_OPTIONS).decode()


def _json_form(value: Any) -> Any:
    """What json.dumps writes for a value it has no form for (see :func:`to_json_value`)."""
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return {name: getattr(value, name) for name in _field_names(type(value))}
    if isinstance(value, enum.Enum):
        return value.value
    if hasattr(value, "item"):  # a numpy scalar
        return value.item()
    raise TypeError(f"{type(value).__name__} has no JSON form")

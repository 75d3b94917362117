"""Whatever arrives, decode_client returns a valid message or raises ProtocolError."""

from __future__ import annotations

import json
from typing import Any

from hypothesis import given, settings
from hypothesis import strategies as st

from tests.protocol.strategies import for_message, hostile_values
from workcell.protocol import messages as m
from workcell.protocol.codec import ProtocolError, decode_client, encode

CLIENT = tuple(m.CLIENT_MESSAGES)


def check(data: str | bytes) -> None:
    try:
        message = decode_client(data)
    except ProtocolError as error:
        assert error.code in ("malformed", "too_large", "invalid_value")
        assert str(error)
        return
    assert isinstance(message, CLIENT)
    assert decode_client(encode(message)) == message  # what passes is canonical


@settings(max_examples=300, deadline=None)
@given(st.binary(max_size=300))
def test_arbitrary_bytes(data: bytes) -> None:
    check(data)


@settings(max_examples=300, deadline=None)
@given(hostile_values)
def test_arbitrary_json(value: Any) -> None:
    check(json.dumps(value))


FIELD_NAMES = st.sampled_from(
    [
        "role",
        "resume_token",
        "settings",
        "seq",
        "t_client",
        "source",
        "headset",
        "left",
        "right",
        "pose",
        "grip",
        "x",
    ]
)


@settings(max_examples=300, deadline=None)
@given(
    st.sampled_from(["hello", "start_session", "input", "stop", "ping"]),
    st.dictionaries(FIELD_NAMES, hostile_values, max_size=6),
)
def test_objects_with_a_known_type(kind: str, fields: dict[str, Any]) -> None:
    check(json.dumps({**fields, "type": kind}))


def _mutate(value: Any, path: list[int], replacement: Any) -> Any:
    """``value`` with the node reached by ``path`` (indices into children) replaced."""
    if not path:
        return replacement
    if isinstance(value, dict) and value:
        key = sorted(value)[path[0] % len(value)]
        return {**value, key: _mutate(value[key], path[1:], replacement)}
    if isinstance(value, list) and value:
        index = path[0] % len(value)
        return [*value[:index], _mutate(value[index], path[1:], replacement), *value[index + 1 :]]
    return replacement


@settings(max_examples=400, deadline=None)
@given(
    st.sampled_from(CLIENT).flatmap(for_message),
    st.lists(st.integers(0, 10), min_size=1, max_size=4),
    hostile_values
    | st.sampled_from([float("nan"), float("inf"), 1e308, -(2**64), 10**400, True, None]),
)
def test_valid_messages_with_one_part_replaced(message: Any, path: list[int], new: Any) -> None:
    data = _mutate(json.loads(encode(message)), path, new)
    check(json.dumps(data))

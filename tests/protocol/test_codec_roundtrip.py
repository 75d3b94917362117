"""Every message type survives encode → decode unchanged."""

from __future__ import annotations

import dataclasses
import functools
import json
import math
from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from tests.protocol.strategies import for_message
from workcell.protocol import messages as m
from workcell.protocol.api import API_TYPES
from workcell.protocol.codec import decode_client, decode_server, encode, to_json_value
from workcell.protocol.validation import build
from workcell.task.hud import Hud, HudPhase


@pytest.mark.parametrize("cls", m.CLIENT_MESSAGES, ids=lambda c: c.__name__)
@settings(max_examples=60, deadline=None)
@given(data=st.data())
def test_client_messages_round_trip(cls: type, data: st.DataObject) -> None:
    message = data.draw(for_message(cls))
    assert decode_client(encode(message)) == message
    assert decode_client(encode(message).encode()) == message


@pytest.mark.parametrize("cls", m.SERVER_MESSAGES, ids=lambda c: c.__name__)
@settings(max_examples=40, deadline=None)
@given(data=st.data())
def test_server_messages_round_trip(cls: type, data: st.DataObject) -> None:
    message = data.draw(for_message(cls))
    assert decode_server(encode(message)) == message


def test_encoding_is_compact_json_with_type_field() -> None:
    text = encode(m.Stop())
    assert text == '{"reason":"","type":"stop"}'
    assert json.loads(encode(m.Ping(t_client=1.5))) == {
        "t_client": 1.5,
        "rtt_ms": None,
        "type": "ping",
    }


def test_fields_with_defaults_may_be_left_out() -> None:
    assert decode_client('{"type":"hello","role":"spectator"}') == m.Hello(role="spectator")


def test_directions_are_separate() -> None:
    from workcell.protocol.codec import ProtocolError

    with pytest.raises(ProtocolError, match="must be one of"):
        decode_client(encode(m.Pong(t_client=1.0, t_server=2.0)))
    with pytest.raises(ProtocolError):
        decode_server(encode(m.Stop()))


@pytest.mark.parametrize("cls", API_TYPES, ids=lambda c: c.__name__)
@settings(max_examples=15, deadline=None)
@given(data=st.data())
def test_api_bodies_round_trip(cls: type, data: st.DataObject) -> None:
    body = data.draw(for_message(cls))
    assert build(cls, json.loads(encode(body)), cls.__name__) == body


def _converted(message: object) -> str:
    """The JSON of the message converted as a whole first (what encode writes, but for
    non-ASCII characters, which encode writes as UTF-8 and this escapes)."""
    return json.dumps(to_json_value(message), separators=(",", ":"), allow_nan=False)


def _same_json(text: str, message: object) -> bool:
    """``text`` is the JSON of ``message`` converted as a whole first: the same keys in the
    same order and the same values, floats to the bit (both write a float's shortest
    round-tripping form, though not always alike: ``0.00001`` and ``1e-05``)."""
    ordered = functools.partial(json.loads, object_pairs_hook=list)
    return bool(ordered(text) == ordered(_converted(message)))


@pytest.mark.parametrize(
    "cls", (*m.CLIENT_MESSAGES, *m.SERVER_MESSAGES, *API_TYPES), ids=lambda c: c.__name__
)
@settings(max_examples=25, deadline=None)
@given(data=st.data())
def test_encoding_in_one_pass_writes_the_converted_json(cls: type, data: st.DataObject) -> None:
    message = data.draw(for_message(cls))
    assert _same_json(encode(message), message)


def test_a_state_with_numpy_values_and_a_non_finite_float_is_written_as_converted() -> None:
    pose: Any = (np.float64(0.5), 1.0, np.float32(0.25), 1.0, 0.0, 0.0, 0.0)
    hud = Hud(
        HudPhase.RUNNING,
        "practice",
        0,
        None,
        None,
        None,
        0,
        1,
        0.0,
        39.79,
        0,
        "box_transfer",
        "lifted",
        40,
        "Carry the box from the conveyor to the delivery table.",
    )
    state = m.State(
        seq=np.int64(3),  # type: ignore[arg-type]  # what a careless builder might pass
        t_sim=1.5,
        poses=(pose, (math.nan, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0)),
        hud=hud,
        input_seq=2,
        tcp_targets=(pose, pose),
        following=(True, False),
    )
    text = encode(state)
    assert _same_json(text, state)
    assert '"phase":"running"' in text and "[null,0.0" in text and '"seq":3' in text
    finite = dataclasses.replace(state, poses=(pose,))
    assert _same_json(encode(finite), finite)


def test_non_ascii_text_is_written_as_utf_8_and_read_back_the_same() -> None:
    message = m.Error(code="invalid_value", message="Étagère du haut — café")
    text = encode(message)
    assert "Étagère du haut — café" in text
    assert decode_server(text) == message

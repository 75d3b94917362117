"""Every message type survives encode → decode unchanged."""

from __future__ import annotations

import json

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from tests.protocol.strategies import for_message
from workcell.protocol import messages as m
from workcell.protocol.api import API_TYPES
from workcell.protocol.codec import decode_client, decode_server, encode
from workcell.protocol.validation import build


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
    assert text == '{"type":"stop"}'
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

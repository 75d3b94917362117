"""Hostile or broken client messages: one ProtocolError naming the field and the rule."""

from __future__ import annotations

import json
import math
from typing import Any

import pytest

from workcell.protocol import messages as m
from workcell.protocol.codec import (
    LONE_SURROGATE,
    MAX_MESSAGE_BYTES,
    ProtocolError,
    decode_client,
    decode_server,
    encode,
)

HAND = m.ControllerState(
    pose=(0.1, 1.0, -0.3, 1.0, 0.0, 0.0, 0.0), grip=0.0, trigger=0.0, stick=(0.0, 0.0), buttons=0
)
INPUT = m.Input(seq=1, t_client=0.0, source="xr", headset=None, left=HAND, right=HAND)


def input_with(path: str, value: Any) -> str:
    """The valid INPUT message as JSON text with one field (dotted path) replaced."""
    data = json.loads(encode(INPUT))
    *parents, last = path.split(".")
    node = data
    for part in parents:
        node = node[part]
    node[last] = value
    return json.dumps(data)


@pytest.mark.parametrize(
    ("text", "code", "says"),
    [
        (
            input_with("left.grip", 1.5),
            "invalid_value",
            "input.left.grip = 1.5: must be from 0 to 1",
        ),
        (input_with("right.trigger", -0.1), "invalid_value", "input.right.trigger"),
        (input_with("left.stick", [0.0, 2.0]), "invalid_value", "input.left.stick"),
        (input_with("left.buttons", 1.5), "malformed", "input.left.buttons = 1.5: must be a whole"),
        (input_with("left.grip", True), "malformed", "input.left.grip = True: must be a number"),
        (input_with("left.grip", "0.5"), "malformed", "must be a number"),
        (input_with("seq", -1), "invalid_value", "input.seq"),
        (input_with("seq", 2**60), "invalid_value", "input.seq"),
        (input_with("source", "mouse"), "malformed", "input.source = 'mouse': must be one of"),
        (input_with("left.pose", [0, 1, 0, 2, 0, 0, 0]), "invalid_value", "unit quaternion"),
        (input_with("left.pose", [0, 1, 0, 0, 0, 0, 0]), "invalid_value", "its norm is 0"),
        (input_with("left.pose", [1e6, 1, 0, 1, 0, 0, 0]), "invalid_value", "within 100 m"),
        (input_with("left.pose", [0, 1, 0, 1, 0, 0]), "malformed", "list of 7 items, got 6"),
        (input_with("headset", {"x": 1}), "malformed", "input.headset"),
        (input_with("left.extra", 1), "malformed", "input.left.extra: unknown field"),
        ('{"type":"ping","t_client":1e400}', "invalid_value", "ping.t_client = inf: must be a"),
        ('{"type":"ping","t_client":NaN}', "invalid_value", "ping.t_client = nan: must be a"),
        ('{"type":"ping","t_client":-Infinity}', "invalid_value", "ping.t_client = -inf"),
        (
            input_with("headset", [0, 1, 0, float("nan"), 0, 0, 0]),
            "invalid_value",
            "input.headset[3] = nan: must be a finite number",
        ),
        (
            '{"type":"start_session","settings":{"task":{"time_limit_s":NaN}}}',
            "invalid_value",
            "start_session.settings.task.time_limit_s = nan",
        ),
        ('{"type":"ping"}', "malformed", "ping.t_client: missing"),
        ('{"type":"launch_missiles"}', "malformed", "type = 'launch_missiles': must be one of"),
        ('{"role":"operator"}', "malformed", "must be one of"),
        ("[1, 2]", "malformed", "must be a JSON object"),
        ("{", "malformed", "not JSON"),
        ("", "malformed", "not JSON"),
        (b"\xff\xfe", "malformed", "not UTF-8"),
        ("[" * 50_000 + "]" * 50_000, "too_large", "at most 65536"),
        ("[" * 20_000 + "]" * 20_000, "malformed", ""),
        (
            '{"type":"hello","role":"operator","resume_token":"' + "x" * 200 + '"}',
            "invalid_value",
            "at most 128 characters",
        ),
        ('{"type":"start_session","settings":[1]}', "malformed", "start_session.settings"),
        ('{"type":"ping","t_client":1' + "0" * 5000 + "}", "malformed", ""),
        # integers of any length are valid JSON, but not every one is a float
        (
            '{"type":"ping","t_client":1' + "0" * 400 + "}",
            "invalid_value",
            "ping.t_client = 1000000000000000000000000000000000000...: must be a finite number",
        ),
        (input_with("t_client", -(10**400)), "invalid_value", "input.t_client = -100000"),
        (input_with("left.grip", 10**309), "invalid_value", "input.left.grip = 1000"),
        (input_with("left.stick", [0, 10**400]), "invalid_value", "input.left.stick[1] = 1000"),
        (input_with("headset", [0, 1, 0, 10**400, 0, 0, 0]), "invalid_value", "headset[3]"),
        (
            '{"type":"start_session","settings":{"task":{"time_limit_s":1' + "0" * 400 + "}}}",
            "invalid_value",
            "start_session.settings.task.time_limit_s = 1000",
        ),
        (
            '{"type":"start_session","settings":{"seed":[2,-1' + "0" * 309 + "]}}",
            "invalid_value",
            "start_session.settings.seed[1] = -10000000000000000000000000000000000",
        ),
    ],
)
def test_refused_with_code_and_field(text: str | bytes, code: str, says: str) -> None:
    with pytest.raises(ProtocolError) as refused:
        decode_client(text)
    assert refused.value.code == code
    assert says in str(refused.value)


def test_size_limit_counts_bytes() -> None:
    padding = "é" * (MAX_MESSAGE_BYTES // 2)  # two bytes each in UTF-8
    with pytest.raises(ProtocolError, match="at most") as refused:
        decode_client('{"type":"start_session","settings":{"a":"' + padding + '"}}')
    assert refused.value.code == "too_large"


def test_slightly_off_quaternion_is_normalised() -> None:
    s = 1.004  # a float32 headset's norm is off by far less; 1e-2 is allowed
    decoded = decode_client(input_with("left.pose", [0.1, 1.0, -0.3, s, 0, 0, 0]))
    assert isinstance(decoded, m.Input)
    assert decoded.left.pose is not None
    assert decoded.left.pose[3:] == (1.0, 0.0, 0.0, 0.0)
    quat = decode_client(input_with("left.pose", [0, 0, 0, 0.5, 0.5, 0.5, 0.501]))
    assert isinstance(quat, m.Input) and quat.left.pose is not None
    assert math.isclose(math.sqrt(sum(q * q for q in quat.left.pose[3:])), 1.0, abs_tol=1e-12)


def test_integers_are_accepted_as_numbers() -> None:
    decoded = decode_client('{"type":"ping","t_client":3}')
    assert decoded == m.Ping(t_client=3.0)
    assert isinstance(decoded, m.Ping) and type(decoded.t_client) is float


def test_a_refused_value_comes_with_its_path_value_and_rule_as_data() -> None:
    with pytest.raises(ProtocolError) as caught:
        decode_client(input_with("left.stick", [0.0, 2.0]))
    problem = caught.value.problem
    assert problem is not None
    assert problem.path == ("input", "left", "stick")
    assert problem.value == [0.0, 2.0]
    assert problem.allowed == "must be from -1 to 1"
    assert problem.message == str(caught.value)
    sent = json.loads(
        encode(m.Error(code="invalid_value", message=problem.message, problem=problem))
    )
    assert sent["problem"]["path"] == ["input", "left", "stick"]


@pytest.mark.parametrize("value", [2**60, 10**400])
def test_a_value_a_browser_cannot_hold_is_sent_as_null(value: int) -> None:
    with pytest.raises(ProtocolError) as caught:
        decode_client(input_with("seq", value))
    problem = caught.value.problem
    assert problem is not None
    assert problem.path == ("input", "seq")
    assert problem.value is None
    error = m.Error(code=caught.value.code, message=str(caught.value), problem=problem)
    assert decode_server(encode(error)) == error


@pytest.mark.parametrize("value", [-(2**64), 2**63, 10**30])
def test_free_form_integers_beyond_64_bits_are_refused_not_echoed(value: int) -> None:
    """Settings are free-form JSON: an integer a float holds but the encoder (64 bits) does
    not is refused with its path, so a message that decodes always encodes again (a
    hostile StartSession once decoded and then failed to encode)."""
    text = json.dumps({"type": "start_session", "settings": {"session": {"seed": value}}})
    with pytest.raises(ProtocolError) as caught:
        decode_client(text)
    problem = caught.value.problem
    assert caught.value.code == "invalid_value"
    assert problem is not None and problem.path == ("start_session", "settings", "session", "seed")
    assert problem.allowed == "must be within -2^63 to 2^63 - 1"
    error = m.Error(code=caught.value.code, message=str(caught.value), problem=problem)
    assert decode_server(encode(error)) == error


def test_a_seed_of_63_bits_still_passes_in_settings() -> None:
    text = json.dumps({"type": "start_session", "settings": {"session": {"seed": 2**63 - 1}}})
    message = decode_client(text)
    assert isinstance(message, m.StartSession)
    assert decode_client(encode(message)) == message


@pytest.mark.parametrize(
    "text",
    [
        '{"type":"stop","reason":"\\ud800 my words"}',
        '{"type":"stop","reason":"\\uDFFF"}',
        '{"type":"start_session","settings":{"\\udbff":1}}',
        '{"type":"start_session","settings":{"session":{"operator_id":["a","\\ud83d"]}}}',
        '{"type":"ping","t_client":"\\ud83d"}',
    ],
)
def test_a_lone_surrogate_is_refused_wherever_it_stands(text: str) -> None:
    """JSON escapes a lone UTF-16 surrogate and Python decodes it, but nothing after the
    decoder can write it (the encoder, the store's UTF-8): one error, itself writable."""
    with pytest.raises(ProtocolError) as caught:
        decode_client(text)
    assert (caught.value.code, str(caught.value)) == ("malformed", LONE_SURROGATE)
    error = m.Error(code=caught.value.code, message=str(caught.value))
    assert decode_server(encode(error)) == error


def test_a_surrogate_pair_is_one_character_and_passes() -> None:
    message = decode_client('{"type":"stop","reason":"\\ud83d\\ude00 done, \\\\ud800 typed"}')
    assert message == m.Stop(reason="\U0001f600 done, \\ud800 typed")
    assert decode_client(encode(message)) == message


@pytest.mark.parametrize("depth", [65, 300, 900])
def test_free_form_json_nested_deeper_than_the_encoder_writes_is_refused(depth: int) -> None:
    """orjson writes at most 255 levels: settings nested deeper decoded, and the reply
    that named them (ConfigRejected) could not be written; deep nesting with a lone
    surrogate at its bottom is refused too, not raised as RecursionError."""
    for leaf in ("1", '"\\ud800"'):
        text = '{"type":"start_session","settings":{"a":' + "[" * depth + leaf + "]" * depth + "}}"
        with pytest.raises(ProtocolError) as caught:
            decode_client(text)
        assert caught.value.code == "malformed"
        error = m.Error(
            code=caught.value.code, message=str(caught.value), problem=caught.value.problem
        )
        assert decode_server(encode(error)) == error


def test_free_form_json_nested_64_deep_passes_and_encodes() -> None:
    text = '{"type":"start_session","settings":{"a":' + "[" * 64 + "1" + "]" * 64 + "}}"
    message = decode_client(text)
    assert decode_client(encode(message)) == message
    with pytest.raises(ProtocolError, match="must nest at most 64 levels deep"):
        decode_client(text.replace("[", "[[", 1).replace("]", "]]", 1))

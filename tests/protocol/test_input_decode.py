"""The Input's fast path decodes what the general path decodes, value for value, and
leaves everything else to it (issue 38)."""

from __future__ import annotations

import json
import math
from typing import Any

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from workcell.protocol import messages as m
from workcell.protocol.codec import decode_client
from workcell.protocol.input_decode import quick_input
from workcell.protocol.validation import ProtocolError, build

# Valid values as a browser writes them (whole numbers without a point) ...
UNIT = st.one_of(st.sampled_from([0, 1, 0.0, 1.0, 0.5]), st.floats(0, 1))
STICK = st.one_of(st.sampled_from([0, -1, 1, 0.0]), st.floats(-1, 1))
QUATERNION = st.sampled_from([[1, 0, 0, 0], [0.7071, 0.7071, 0, 0], [0.999, 0.01, 0, 0.004],
                              [0.5, 0.5, 0.5, 0.5], [1.005, 0, 0, 0]])  # fmt: skip
POSE = st.one_of(
    st.none(),
    st.builds(
        lambda position, quaternion: [*position, *quaternion],
        st.lists(st.floats(-3, 3), min_size=3, max_size=3),
        QUATERNION,
    ),
)
HAND = st.fixed_dictionaries(
    {
        "pose": POSE,
        "grip": UNIT,
        "trigger": UNIT,
        "stick": st.lists(STICK, min_size=2, max_size=2),
        "buttons": st.integers(0, 255),
    }
)
VALID = st.fixed_dictionaries(
    {
        "type": st.just("input"),
        "seq": st.integers(0, 2**53 - 1),
        "t_client": st.one_of(st.floats(1e9, 2e9), st.integers(0, 2**40)),
        "source": st.sampled_from(["xr", "desktop", "gamepad"]),
        "headset": POSE,
        "left": HAND,
        "right": HAND,
    }
)
# ... and the ways one of them goes wrong (or is unusual): a value replaced at one place.
ODD: st.SearchStrategy[Any] = st.sampled_from(
    [None, True, False, -1, 2, 256, 1.5, -1.5, 2**53, 2**60, 1e300, math.inf, -math.inf,
     math.nan, "1", [], {}, [0, 0], [0, 0, 0, 1, 0, 0, 0], [0, 0, 0, 2, 0, 0, 0],
     [101, 0, 0, 1, 0, 0, 0], [0, 0, 0, 1, 0, 0], "XR"]
)  # fmt: skip
PLACES = [("seq",), ("t_client",), ("source",), ("headset",), ("unknown",), ("left",)] + [
    (side, key) for side in ("left", "right")
    for key in ("pose", "grip", "trigger", "stick", "buttons", "extra")
]  # fmt: skip


@st.composite
def inputs(draw: st.DrawFn) -> dict[str, Any]:
    data: dict[str, Any] = draw(VALID)
    if draw(st.booleans()):
        place = draw(st.sampled_from(PLACES))
        value = draw(ODD)
        if len(place) == 1:
            data[place[0]] = value
        else:
            data[place[0]] = {**data[place[0]], place[1]: value}
    if draw(st.booleans()) and data["headset"] is not None:
        del data["headset"]  # a field missing
    return data


def _general(data: dict[str, Any]) -> m.Input | ProtocolError:
    try:
        message: m.Input = build(m.Input, data, "input")
    except ProtocolError as error:
        return error
    return message


@settings(max_examples=1500, deadline=None)
@given(data=inputs())
def test_the_fast_path_builds_what_the_general_path_builds(data: dict[str, Any]) -> None:
    quick = quick_input(data)
    general = _general(data)
    if quick is not None:
        assert general == quick
    decoded: m.ClientMessage | ProtocolError
    try:
        decoded = decode_client(json.dumps(data))
    except ProtocolError as error:
        decoded = error
    if isinstance(general, ProtocolError):
        assert isinstance(decoded, ProtocolError)
        assert (str(decoded), decoded.code) == (str(general), general.code)
    else:
        assert decoded == general


def test_a_browsers_input_takes_the_fast_path() -> None:
    hand = {"pose": [0.2, 1.1, -0.3, 1, 0, 0, 0], "grip": 1, "trigger": 0.25,
            "stick": [0, -0.5], "buttons": 3}  # fmt: skip
    data = {"type": "input", "seq": 7, "t_client": 1733400000.5, "source": "xr",
            "headset": [0, 1.6, 0, 0.99999, 0, 0.004, 0], "left": hand, "right": hand}  # fmt: skip
    quick = quick_input(data)
    assert quick is not None
    assert quick == build(m.Input, data, "input")
    assert quick.left.grip == 1.0 and type(quick.left.grip) is float


@pytest.mark.parametrize(
    ("where", "value", "problem"),
    [
        ("grip", 1.5, "input.left.grip = 1.5: must be from 0 to 1"),
        ("buttons", True, "input.left.buttons = True: must be a whole number"),
        ("pose", [0, 0, 0, 2, 0, 0, 0], "must be a unit quaternion"),
    ],
)
def test_a_wrong_input_is_refused_by_name_as_before(where: str, value: Any, problem: str) -> None:
    hand = {"pose": None, "grip": 0, "trigger": 0, "stick": [0, 0], "buttons": 0}
    data = {"type": "input", "seq": 1, "t_client": 0, "source": "xr", "headset": None,
            "left": {**hand, where: value}, "right": hand}  # fmt: skip
    assert quick_input(data) is None
    with pytest.raises(ProtocolError, match=problem.replace("[", r"\[")):
        decode_client(json.dumps(data))

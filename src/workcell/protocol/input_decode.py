"""The operator's Input, decoded on a fast path (issue 38).

Every operator sends an :class:`~workcell.protocol.messages.Input` per animation frame
(72 a second from a headset), and the server's event loop decodes every one of them for
every session: with the general, hint-driven :func:`~workcell.protocol.validation.build`
that was over half of the loop's time with eight operators. :func:`quick_input` checks
the one common shape directly (every field present, numbers finite and in range, poses
bounded with near-unit quaternions) and builds the same message ``build`` would, value
for value (``tests/protocol/test_input_decode.py``); anything else, and anything wrong,
is left to ``build``, which says what is wrong.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any, cast, get_args

from workcell.protocol import messages as m
from workcell.protocol.scene import Pose
from workcell.protocol.validation import (
    MAX_SAFE_INTEGER,
    POSITION_LIMIT_M,
    QUATERNION_TOLERANCE,
    RANGES,
)

_INPUT_FIELDS = frozenset(f.name for f in dataclasses.fields(m.Input))
_HAND_FIELDS = frozenset(f.name for f in dataclasses.fields(m.ControllerState))
_SOURCES = frozenset(get_args(m.InputSource))
_GRIP = RANGES[(m.ControllerState, "grip")]
_TRIGGER = RANGES[(m.ControllerState, "trigger")]
_STICK = RANGES[(m.ControllerState, "stick")]
_BUTTONS = RANGES[(m.ControllerState, "buttons")]
_SEQ = RANGES[(m.Input, "seq")]


class _DeclinedError(Exception):
    """Not the common shape: the general path decides (and names any problem)."""


def quick_input(data: dict[str, Any]) -> m.Input | None:
    """The Input ``data`` (a decoded JSON object of type "input") holds when it has the
    common, valid shape; None when the general path must look at it."""
    if data.keys() != _INPUT_FIELDS:
        return None
    try:
        seq = data["seq"]
        if type(seq) is not int or not _SEQ[0] <= seq <= min(_SEQ[1], MAX_SAFE_INTEGER):
            return None
        source = data["source"]
        if type(source) is not str or source not in _SOURCES:
            return None
        headset = data["headset"]
        return m.Input(
            seq=seq,
            t_client=_number(data["t_client"]),
            source=cast(m.InputSource, source),
            headset=None if headset is None else _pose(headset),
            left=_hand(data["left"]),
            right=_hand(data["right"]),
        )
    except _DeclinedError:
        return None


def _number(value: Any) -> float:
    kind = type(value)
    if kind is float:
        if not math.isfinite(value):
            raise _DeclinedError
        return float(value)
    if kind is int and abs(value) <= MAX_SAFE_INTEGER:
        return float(value)
    raise _DeclinedError


def _within(value: float, bounds: tuple[float, float]) -> float:
    if not bounds[0] <= value <= bounds[1]:
        raise _DeclinedError
    return value


def _numbers(value: Any, count: int) -> tuple[float, ...]:
    if type(value) is not list or len(value) != count:
        raise _DeclinedError
    for item in value:
        kind = type(item)
        if kind is float:
            if not math.isfinite(item):
                raise _DeclinedError
        elif kind is not int or abs(item) > MAX_SAFE_INTEGER:
            raise _DeclinedError
    return tuple(map(float, value))


def _pose(value: Any) -> Pose:
    """As :func:`~workcell.protocol.validation.unit_pose` makes it, in the same
    arithmetic (its quaternion normalised unless its norm is 1 within 1e-12)."""
    x, y, z, qw, qx, qy, qz = _numbers(value, 7)
    if abs(x) > POSITION_LIMIT_M or abs(y) > POSITION_LIMIT_M or abs(z) > POSITION_LIMIT_M:
        raise _DeclinedError
    norm = math.sqrt(qw * qw + qx * qx + qy * qy + qz * qz)
    if abs(norm - 1.0) > QUATERNION_TOLERANCE:
        raise _DeclinedError
    if abs(norm - 1.0) > 1e-12:
        return (x, y, z, qw / norm, qx / norm, qy / norm, qz / norm)
    return (x, y, z, qw, qx, qy, qz)


def _hand(value: Any) -> m.ControllerState:
    if type(value) is not dict or value.keys() != _HAND_FIELDS:
        raise _DeclinedError
    buttons = value["buttons"]
    if type(buttons) is not int or not _BUTTONS[0] <= buttons <= _BUTTONS[1]:
        raise _DeclinedError
    pose = value["pose"]
    x, y = _numbers(value["stick"], 2)
    return m.ControllerState(
        pose=None if pose is None else _pose(pose),
        grip=_within(_number(value["grip"]), _GRIP),
        trigger=_within(_number(value["trigger"]), _TRIGGER),
        stick=(_within(x, _STICK), _within(y, _STICK)),
        buttons=buttons,
    )

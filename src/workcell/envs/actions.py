"""Action vectors (the ``action`` feature) to and from :class:`Command` values.

The vector follows :data:`workcell.export.features.ACTION_NAMES`. Follow flags are on at
0.5 and above; target quaternions are normalised (a zero one becomes the identity).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from workcell.control.command import ArmCommand, BaseTwist, Command, CommandError
from workcell.export.features import ACTION_NAMES
from workcell.record.columns import POSE_SUFFIXES

FOLLOW_THRESHOLD = 0.5
_INDEX = {name: i for i, name in enumerate(ACTION_NAMES)}


def _at(prefix: str, suffixes: tuple[str, ...]) -> list[int]:
    return [_INDEX[f"{prefix}_{s}"] for s in suffixes]


_BASE = [_INDEX["cmd_vx"], _INDEX["cmd_vy"], _INDEX["cmd_wz"]]
_POSITION = {side: _at(f"target_{side}", POSE_SUFFIXES[:3]) for side in ("l", "r")}
_QUATERNION = {side: _at(f"target_{side}", POSE_SUFFIXES[3:]) for side in ("l", "r")}
_FOLLOW = {side: _INDEX[f"follow_{side}"] for side in ("l", "r")}
_GRIPPER = {side: _INDEX[f"gripper_cmd_{side}"] for side in ("l", "r")}
_HEAD = [_INDEX["head_cmd_pan"], _INDEX["head_cmd_tilt"]]


def _unit(quaternion: NDArray[np.float64]) -> tuple[float, float, float, float]:
    norm = float(np.linalg.norm(quaternion))
    if norm < 1e-9:
        return (1.0, 0.0, 0.0, 0.0)
    w, x, y, z = (float(v) for v in quaternion / norm)
    return (w, x, y, z)


def _arm(action: NDArray[np.float64], side: str) -> ArmCommand:
    x, y, z = (float(v) for v in action[_POSITION[side]])
    return ArmCommand(
        (x, y, z), _unit(action[_QUATERNION[side]]), bool(action[_FOLLOW[side]] >= FOLLOW_THRESHOLD)
    )


def command_from_action(action: NDArray[np.floating] | list[float]) -> Command:
    """The command an action vector stands for (grippers clipped to 0..1)."""
    a = np.asarray(action, dtype=np.float64)
    if a.shape != (len(ACTION_NAMES),):
        raise CommandError(
            f"action of shape {a.shape}: must be ({len(ACTION_NAMES)},), see ACTION_NAMES"
        )
    vx, vy, wz = (float(v) for v in a[_BASE])
    pan, tilt = (float(v) for v in a[_HEAD])
    return Command(
        base=BaseTwist(vx, vy, wz),
        left=_arm(a, "l"),
        right=_arm(a, "r"),
        close_left=float(np.clip(a[_GRIPPER["l"]], 0.0, 1.0)),
        close_right=float(np.clip(a[_GRIPPER["r"]], 0.0, 1.0)),
        head=(pan, tilt),
    )


def action_from_command(command: Command) -> NDArray[np.float32]:
    """The action vector of a command (the inverse of :func:`command_from_action`)."""
    a = np.zeros(len(ACTION_NAMES))
    a[_BASE] = (command.base.vx, command.base.vy, command.base.wz)
    for side, arm in (("l", command.left), ("r", command.right)):
        a[_POSITION[side]] = arm.position
        a[_QUATERNION[side]] = arm.quaternion
        a[_FOLLOW[side]] = float(arm.follow)
    a[_GRIPPER["l"]] = command.close_left
    a[_GRIPPER["r"]] = command.close_right
    a[_HEAD] = command.head
    return a.astype(np.float32)

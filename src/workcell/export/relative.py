"""The objects and the goal as the robot sees them: the last part of
``observation.environment_state``.

The world-frame features (every box's pose, the task's goal) leave to a policy the
subtraction a grasp needs to the centimetre: where the box is from each gripper, and where
box and goal are from the base that must drive there. A state-only ACT trained on world
features alone closed its grippers at a fixed time whether or not its hands were around the
box (``bench/README.md``, ``bench/learn_d1.py``; issue 34, item 0). These features give it
the differences directly, computed from the same recorded frame as the rest, so the exports
and the Gymnasium environment agree:

- per pooled box ``i``: ``box{i}_in_base_x``, ``box{i}_in_base_y`` (its centre in the base
  frame: x forward, y left, m), ``box{i}_in_base_yaw`` (its heading from the base's, rad,
  wrapped to [-pi/2, pi/2): a box turned half a turn is the same box to a gripper), then
  ``box{i}_from_tcp_l_x|y|z`` and ``box{i}_from_tcp_r_x|y|z`` (the box's centre minus the
  left and right TCP positions, in the base frame, m);
- per point of the goal (a ``<p>_x``, ``<p>_y`` pair of :attr:`workcell.tasks.Task.goal_names`,
  a position in the world): ``<p>_in_base_x``, ``<p>_in_base_y``.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from workcell.export.features import STATE_NAMES

TCPS: tuple[str, ...] = ("tcp_l", "tcp_r")
_BASE = tuple(STATE_NAMES.index(name) for name in ("base_x", "base_y", "base_yaw"))
_TCP = {tcp: tuple(STATE_NAMES.index(f"{tcp}_{axis}") for axis in "xyz") for tcp in TCPS}


def box_relative_names(index: int) -> tuple[str, ...]:
    """One pooled box's relative features, in order."""
    box = f"box{index}"
    return (
        f"{box}_in_base_x",
        f"{box}_in_base_y",
        f"{box}_in_base_yaw",
        *(f"{box}_from_{tcp}_{axis}" for tcp in TCPS for axis in "xyz"),
    )


def goal_points(goal_names: Sequence[str]) -> tuple[tuple[int, str], ...]:
    """The goal's world points: (index of its ``_x`` number, the point's name) for each
    ``<p>_x`` directly followed by ``<p>_y``."""
    return tuple(
        (i, name[:-2])
        for i, name in enumerate(goal_names[:-1])
        if name.endswith("_x") and goal_names[i + 1] == name[:-2] + "_y"
    )


def relative_names(pool_size: int, goal_names: Sequence[str]) -> tuple[str, ...]:
    """The names of :func:`relative_features`' columns."""
    boxes = (name for i in range(pool_size) for name in box_relative_names(i))
    points = (f"{p}_in_base_{axis}" for _, p in goal_points(goal_names) for axis in "xy")
    return (*boxes, *points)


def relative_features(
    state: NDArray[np.float64],
    box_poses: NDArray[np.float64],
    goal: NDArray[np.float64],
    goal_names: Sequence[str],
) -> NDArray[np.float64]:
    """(frames, len(relative_names)) from ``state`` (frames, 39: ``observation.state``),
    ``box_poses`` (frames, pool, 7: x, y, z, qw, qx, qy, qz in the world,
    :class:`workcell.export.boxes.BoxTrack`) and ``goal`` (frames, len(goal_names))."""
    n = len(state)
    base_xy = state[:, _BASE[:2]]
    yaw = state[:, _BASE[2]]
    cos, sin = np.cos(yaw), np.sin(yaw)

    def in_base(vectors: NDArray[np.float64]) -> NDArray[np.float64]:
        """World-frame (frames, 2 or 3) vectors turned into the base frame."""
        turned = vectors.copy()
        turned[:, 0] = cos * vectors[:, 0] + sin * vectors[:, 1]
        turned[:, 1] = -sin * vectors[:, 0] + cos * vectors[:, 1]
        return turned

    columns: list[NDArray[np.float64]] = []
    for i in range(box_poses.shape[1]):
        position = box_poses[:, i, :3]
        w, x, y, z = (box_poses[:, i, k] for k in range(3, 7))
        heading = np.arctan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))
        columns.append(in_base(position[:, :2] - base_xy))
        columns.append(_half_turn(heading - yaw)[:, None])
        for tcp in TCPS:
            columns.append(in_base(position - state[:, _TCP[tcp]]))
    for index, _ in goal_points(goal_names):
        columns.append(in_base(goal[:, index : index + 2] - base_xy))
    if not columns:
        return np.zeros((n, 0))
    return np.hstack(columns)


def _half_turn(angle: NDArray[np.float64]) -> NDArray[np.float64]:
    """``angle`` wrapped to [-pi/2, pi/2)."""
    wrapped: NDArray[np.float64] = (angle + np.pi / 2) % np.pi - np.pi / 2
    return wrapped

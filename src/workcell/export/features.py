"""The dataset features, defined once for every export and the Gymnasium environment.

Names are frame column names of :mod:`workcell.record.columns` (public API, no '/'), so a
dataset value traces back to its recorded column:

- ``observation.state`` (39): base pose (x, y, yaw) and world-frame velocity, both TCP poses
  (world position and w, x, y, z quaternion), the 17 joints in manifest order, both gripper
  openings (0 closed .. 1 open);
- ``action`` (23): the operator's command: base twist (base frame), both TCP targets (base
  frame), both follow flags (0/1), both gripper commands (0 open .. 1 closed), head pan and
  tilt;
- ``observation.environment_state``: every box's pose and state code (8 per box, see
  :mod:`workcell.export.boxes`), the task's goal, then both as the robot sees them (9 per
  box, 2 per goal point, see :mod:`workcell.export.relative`).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from workcell.record.columns import BASE_COLUMNS, COMMAND_COLUMNS, GRIPPER_COLUMNS, pose_columns
from workcell.record.quaternion_sign import continuous
from workcell.sim.joints import JOINT_ORDER

STATE_KEY = "observation.state"
ACTION_KEY = "action"
ENVIRONMENT_KEY = "observation.environment_state"
IMAGE_PREFIX = "observation.images."

STATE_NAMES: tuple[str, ...] = (
    *BASE_COLUMNS,
    *pose_columns("tcp_l"),
    *pose_columns("tcp_r"),
    *(f"q_{joint}" for joint in JOINT_ORDER),
    *GRIPPER_COLUMNS,
)
ACTION_NAMES: tuple[str, ...] = COMMAND_COLUMNS
STATE_QUATERNIONS: tuple[tuple[int, int, int, int], ...] = tuple(
    tuple(STATE_NAMES.index(f"{tcp}_{part}") for part in ("qw", "qx", "qy", "qz"))  # type: ignore[misc]
    for tcp in ("tcp_l", "tcp_r")
)
"""Where the left and right TCP quaternions (w, x, y, z) sit in ``observation.state``."""


def image_key(camera: str) -> str:
    """``observation.images.<camera>``."""
    return IMAGE_PREFIX + camera


def continuous_state(state: NDArray[np.float64]) -> NDArray[np.float64]:
    """``observation.state`` rows of one episode with continuous TCP quaternions
    (:mod:`workcell.record.quaternion_sign`): what every recorded frame holds since the
    record keeps them so, and what older records are made to hold on export."""
    result = state.copy()
    columns = np.array(STATE_QUATERNIONS)
    result[:, columns] = continuous(state[:, columns])
    return result


def column_matrix(
    columns: Mapping[str, Sequence[Any] | NDArray[Any]], names: Sequence[str]
) -> NDArray[np.float64]:
    """(frames, len(names)) of the named columns, as float64."""
    return np.column_stack([np.asarray(columns[name], dtype=np.float64) for name in names])

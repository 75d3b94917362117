"""The recorded ``boxes`` frame column, parsed: every box's pose and state at every frame.

A frame stores its boxes as JSON, a list of ``[index, state, x, y, z, qw, qx, qy, qz]``
(see :mod:`workcell.recording.frame_format`). Datasets carry them as numbers: the pose and a
state code per box.
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from workcell.export.errors import IncompatibleSessionsError
from workcell.export.relative import relative_names

BOX_STATE_CODES: dict[str, int] = {"parked": 0, "active": 1, "delivered": 2}
"""A box's state as a number: parked (out of play), active (released), delivered."""
DELIVERED = BOX_STATE_CODES["delivered"]
BOX_FIELDS: tuple[str, ...] = ("x", "y", "z", "qw", "qx", "qy", "qz", "state")
"""Per box: world position (m), orientation (w, x, y, z), state code."""


def box_feature_names(pool_size: int) -> tuple[str, ...]:
    """``box0_x, box0_y, .., box0_state, box1_x, ..`` for a pool of ``pool_size`` boxes."""
    return tuple(f"box{i}_{field}" for i in range(pool_size) for field in BOX_FIELDS)


def environment_names(pool_size: int, goal_names: Sequence[str]) -> tuple[str, ...]:
    """``observation.environment_state``'s names: every box (:func:`box_feature_names`),
    then the task's goal (:attr:`workcell.tasks.Task.goal_names`), then both as the robot
    sees them (:func:`workcell.export.relative.relative_names`)."""
    return (*world_environment_names(pool_size, goal_names), *relative_names(pool_size, goal_names))


def goal_slice(pool_size: int, goal_names: Sequence[str]) -> slice:
    """Where the task's goal sits in ``observation.environment_state``: after the boxes."""
    start = pool_size * len(BOX_FIELDS)
    return slice(start, start + len(goal_names))


def world_environment_names(pool_size: int, goal_names: Sequence[str]) -> tuple[str, ...]:
    """The world-frame part of ``observation.environment_state``: every box, then the goal
    (all there was before the relative features: what an older policy reads)."""
    return (*box_feature_names(pool_size), *goal_names)


@dataclass(frozen=True)
class BoxTrack:
    """Every box at every frame: ``poses`` (frames, boxes, 7) and ``states`` (frames, boxes)."""

    poses: NDArray[np.float64]
    states: NDArray[np.int64]

    @property
    def pool_size(self) -> int:
        return int(self.states.shape[1])

    def features(self) -> NDArray[np.float64]:
        """(frames, boxes * 8) in :func:`box_feature_names` order."""
        n, pool = self.states.shape
        joined = np.concatenate([self.poses, self.states[:, :, None].astype(float)], axis=2)
        return joined.reshape(n, pool * len(BOX_FIELDS))

    def deliveries(self) -> NDArray[np.float64]:
        """Boxes that became delivered at each frame (0 at frame 0)."""
        delivered = self.states == DELIVERED
        counts = np.zeros(len(delivered))
        counts[1:] = np.sum(delivered[1:] & ~delivered[:-1], axis=1)
        return counts


def parse_boxes(column: Sequence[Any] | NDArray[Any], pool_size: int | None = None) -> BoxTrack:
    """Parse a trial's ``boxes`` column; every frame must list ``pool_size`` boxes (by
    default as many as the first frame)."""
    n = len(column)
    if pool_size is None:
        pool_size = len(json.loads(column[0])) if n else 0
    poses = np.zeros((n, pool_size, 7))
    states = np.zeros((n, pool_size), dtype=np.int64)
    for i, text in enumerate(column):
        boxes = json.loads(text)
        if len(boxes) != pool_size:
            raise IncompatibleSessionsError(
                f"frame {i} lists {len(boxes)} boxes where the session's pool has {pool_size}"
            )
        for entry in boxes:
            index = int(entry[0])
            states[i, index] = BOX_STATE_CODES[entry[1]]
            poses[i, index] = entry[2:9]
    return BoxTrack(poses, states)

"""One trial's frames as a dataset episode: observations, actions, rewards and flags.

Row ``t`` is recorded frame ``t`` (``frame_index`` equals the store's, ``timestamp`` is
``t / fps``). Conventions, the same in every export and in the Gymnasium environment:

- **action** at row ``t`` is the command the operator gave *after* observing frame ``t``:
  the command recorded with frame ``t + 1`` (a frame stores the command of the control
  period that led to it). The last row repeats its own recorded command. Replaying
  actions ``0 .. n-2`` from the trial's start reproduces frames ``1 .. n-1``.
- **next.reward** is 1.0 for each box delivered at that frame (the frame at which a box's
  state became ``delivered``), else 0. A successful one-box trial has exactly one reward,
  on its last row.
- **next.done** is true on the last row of every episode (success, failure, timeout or
  interruption); **next.success** is true on the last row of a successful trial.
- **intervention** is true on the rows a person who took over from the trial's autonomous
  driver drove (the frame's ``intervention`` column; false where it is 0 or was not
  recorded, before schema version 6): LeRobot's name for a corrected frame.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from workcell.export.boxes import BoxTrack, parse_boxes
from workcell.export.features import (
    ACTION_NAMES,
    STATE_NAMES,
    column_matrix,
    continuous_state,
)
from workcell.export.relative import relative_features

CONVENTIONS: dict[str, str] = {
    "action": "row t holds the command given after observing frame t (recorded with frame "
    "t+1); the last row repeats its own recorded command",
    "next.reward": "1.0 per box delivered at that frame (its state became delivered), else 0",
    "next.done": (
        "true on the last row of every episode (success, failure, timeout or interruption)"
    ),
    "next.success": "true on the last row of a successful trial",
    "intervention": "true where a person who took over from the trial's driver drove the "
    "frame (a correction), false where the driver drove or nothing was recorded",
    "timestamp": "frame_index / fps, seconds from the trial start (t_sim)",
    "observation.state": "TCP quaternions (w, x, y, z) continuous: each frame's sign agrees "
    "with the frame before (non-negative dot product); the first frame's has w >= 0",
}
"""The conventions above, as written into every export's metadata."""


@dataclass(frozen=True)
class EpisodeArrays:
    """A trial's rows, one per recorded frame, at full precision (formats that store
    float32, as LeRobot does, convert when they write)."""

    state: NDArray[np.float64]
    action: NDArray[np.float64]
    environment: NDArray[np.float64]
    reward: NDArray[np.float64]
    done: NDArray[np.bool_]
    success: NDArray[np.bool_]
    boxes: BoxTrack
    intervention: NDArray[np.bool_]
    """True on the rows a person who took over drove (see the module docstring)."""

    @property
    def length(self) -> int:
        return len(self.state)

    def timestamps(self, fps: int) -> NDArray[np.float32]:
        """Seconds from the episode start, ``frame_index / fps``."""
        return (np.arange(self.length) / fps).astype(np.float32)


def next_commands(recorded: NDArray[np.float64]) -> NDArray[np.float64]:
    """Recorded commands (one per frame) shifted to the action convention above."""
    if len(recorded) == 0:
        return recorded.copy()
    return np.concatenate([recorded[1:], recorded[-1:]])


def episode_arrays(
    frames: Mapping[str, Sequence[Any] | NDArray[Any]],
    outcome: str | None,
    pool_size: int,
    goal: Sequence[float],
    goal_names: Sequence[str],
) -> EpisodeArrays:
    """The episode of one trial's frame columns (``Store.frames``); ``goal`` (the trial's
    task goal, :meth:`workcell.tasks.Task.goal`, named ``goal_names``) follows the boxes in
    every row's environment state, then both as the robot sees them
    (:mod:`workcell.export.relative`)."""
    boxes = parse_boxes(frames["boxes"], pool_size)
    n = len(boxes.states)
    goals = np.tile(np.asarray(goal, dtype=np.float64), (n, 1))
    state = continuous_state(column_matrix(frames, STATE_NAMES))
    relative = relative_features(state, boxes.poses, goals, goal_names)
    done = np.zeros(n, dtype=bool)
    done[-1:] = True
    success = done & (outcome == "success")
    return EpisodeArrays(
        state=state,
        action=next_commands(column_matrix(frames, ACTION_NAMES)),
        environment=np.hstack([boxes.features(), goals, relative]),
        reward=boxes.deliveries(),
        done=done,
        success=success,
        boxes=boxes,
        intervention=corrected_rows(frames, n),
    )


def corrected_rows(frames: Mapping[str, Sequence[Any] | NDArray[Any]], n: int) -> NDArray[np.bool_]:
    """Each frame's ``intervention`` as a boolean (False where not recorded)."""
    if "intervention" not in frames:
        return np.zeros(n, dtype=bool)
    values = np.asarray(frames["intervention"], dtype=np.float64)
    corrected: NDArray[np.bool_] = np.nan_to_num(values, nan=0.0) == 1.0
    return corrected

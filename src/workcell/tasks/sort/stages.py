"""How far a sort trial got: its stages, in order.

``none``
    no gripper touched a box.
``touched``
    a gripper touched a box.
``grasped``
    both pads closed on a box (the grasp holds it).
``lifted``
    a held box rose at least :data:`LIFT_M` above its height when the hold began.
``over_own_table``
    a held box was above its own kind's zone (its x, y inside the zone's rectangle).
``sorted_one``
    a box was sorted: it rested released in its own kind's zone for a second.
``all_sorted``
    every box the trial asked for was sorted (the task done).
"""

from __future__ import annotations

from typing import Literal, get_args

SortStage = Literal[
    "none", "touched", "grasped", "lifted", "over_own_table", "sorted_one", "all_sorted"
]
SORT_STAGES: tuple[SortStage, ...] = get_args(SortStage)
LIFT_M = 0.05
"""How far above its height at the start of a hold a held box must rise to count as lifted."""


class SortStageTracker:
    """The stage of one trial, taken in frame by frame."""

    def __init__(self) -> None:
        self.touched = False
        self.grasped = False
        self.lifted = False
        self.over_own_table = False
        self._held: int | None = None
        self._start_z = 0.0

    def touch(self) -> None:
        self.touched = True

    def hold(self, box: int, z: float, over_own_table: bool) -> None:
        """A frame in which ``box`` was held, its centre at height ``z``."""
        self.grasped = True
        if box != self._held:
            self._held, self._start_z = box, z
        if z - self._start_z >= LIFT_M:
            self.lifted = True
        if over_own_table:
            self.over_own_table = True

    def release(self) -> None:
        """A frame in which no box was held."""
        self._held = None

    def stage(self, sorted_boxes: int, required: int) -> SortStage:
        if sorted_boxes >= required:
            return "all_sorted"
        if sorted_boxes >= 1:
            return "sorted_one"
        if self.over_own_table:
            return "over_own_table"
        if self.lifted:
            return "lifted"
        if self.grasped:
            return "grasped"
        return "touched" if self.touched else "none"

"""How far a box-transfer trial got: its stages, defined once for the live judge
(:mod:`workcell.tasks.box_transfer.judge`) and the audit (read from the recorded frames,
:mod:`workcell.audit.task_stages`), which therefore agree.

Stages, in order (definition version 1):

``none``
    no gripper touched a box.
``touched``
    a gripper touched a box.
``grasped``
    both pads closed on a box (the grasp holds it).
``lifted``
    a held box rose at least :data:`LIFT_M` above its height when the hold began.
``over_zone``
    a held box was above the delivery zone (its x, y inside the zone's rectangle).
``delivered``
    a box was delivered.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal, get_args

TaskStage = Literal["none", "touched", "grasped", "lifted", "over_zone", "delivered"]
TASK_STAGES: tuple[TaskStage, ...] = get_args(TaskStage)
TASK_STAGES_VERSION = "1"
LIFT_M = 0.05
"""How far above its height at the start of a hold a held box must rise to count as lifted."""
COMPLETED_COLUMN = "boxes_delivered"
"""The trial column that counts its delivered boxes: a trial with one is ``delivered``
without reading its frames (the audit reads it from here)."""
FRAME_STAGES_TEXT = (
    f"(definition v{TASK_STAGES_VERSION}): a gripper touched a box, both pads closed on it, "
    f"it was lifted {LIFT_M * 100:.0f} cm, carried over the delivery zone, delivered. A "
    "timeout that carried its box over the zone is not one that never moved"
)
"""How the stages are read from the frames, as the audit's report says it."""


@dataclass(frozen=True)
class Zone:
    """A trial's delivery zone on the floor plane: centre and size (x, y), in metres."""

    center: tuple[float, float]
    size: tuple[float, float]

    def contains(self, x: float, y: float) -> bool:
        return (
            abs(x - self.center[0]) <= self.size[0] / 2
            and abs(y - self.center[1]) <= self.size[1] / 2
        )


@dataclass(frozen=True)
class Hold:
    """One frame in which a box was held: its frame index and the held box's position."""

    frame_index: int
    box: int
    x: float
    y: float
    z: float


class StageTracker:
    """The stage of one trial, taken in frame by frame: touches, then holds in frame order."""

    def __init__(self, zone: Zone) -> None:
        self.zone = zone
        self.touched = False
        self.grasped = False
        self.lifted = False
        self.over_zone = False
        self._previous: Hold | None = None
        self._start_z: dict[int, float] = {}

    def touch(self) -> None:
        """A gripper touched a box."""
        self.touched = True

    def grasp(self) -> None:
        """Both pads closed on a box (whether or not its position is known)."""
        self.grasped = True

    def hold(self, hold: Hold) -> None:
        """A frame in which a box was held, at a known position."""
        self.grasped = True
        previous = self._previous
        if (
            previous is None
            or previous.box != hold.box
            or hold.frame_index != previous.frame_index + 1
        ):
            self._start_z[hold.box] = hold.z
        self._previous = hold
        if hold.z - self._start_z[hold.box] >= LIFT_M:
            self.lifted = True
        if self.zone.contains(hold.x, hold.y):
            self.over_zone = True

    def stage(self, boxes_delivered: int | None) -> TaskStage:
        """The furthest stage reached, given the trial's deliveries so far."""
        if boxes_delivered is not None and boxes_delivered >= 1:
            return "delivered"
        if self.over_zone:
            return "over_zone"
        if self.lifted:
            return "lifted"
        if self.grasped:
            return "grasped"
        return "touched" if self.touched else "none"

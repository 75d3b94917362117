"""Lift a box off the conveyor: success once a box has been held at least ``LIFT_M`` above
where the hold began for ``HOLD_S`` (a settled lift, never one transient frame)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any, ClassVar

from workcell.expert.skill import ExpertConfig
from workcell.sim.config import WorldConfig
from workcell.sim.events import WorldEvent
from workcell.sim.world import TaskScene, World
from workcell.task.operator import Operator
from workcell.tasks import Evaluation, Task, WorldName
from workcell.tasks.box_transfer.scene import BoxTransferScene
from workcell.tasks.box_transfer.task import BoxTransfer
from workcell.tasks.elements.expert import ExpertOperator

LIFT_M = 0.05
"""How far above its height when the hold began a box must be held."""
HOLD_S = 1.0
"""How long it must stay up (on the frame clock)."""
FRAME_S = 0.05
"""One recorded frame at the default 20 Hz: the judge is asked once a frame."""


class LiftJudge:
    """Watches the held box at each frame instant."""

    def __init__(self) -> None:
        self.stage = "none"
        self._start_z: float | None = None
        self._held_box: int | None = None
        self._up_frames = 0

    @property
    def done(self) -> int:
        return int(self.stage == "held_up")

    def observe(self, event: WorldEvent) -> None:
        """Nothing in the world's events decides a lift: the judge reads the world."""

    def evaluate(self, world: World) -> Evaluation:
        grasp = world.grasp
        held = grasp.holding
        if held is None:
            self._held_box, self._start_z, self._up_frames = None, None, 0
            touching = grasp.contact_l is not None or grasp.contact_r is not None
            if self.stage == "none" and touching:
                self.stage = "touched"
        else:
            z = float(world.boxes.position(world.data, held)[2])
            if held.index != self._held_box:
                self._held_box, self._start_z, self._up_frames = held.index, z, 0
            assert self._start_z is not None
            up = z - self._start_z >= LIFT_M
            self._up_frames = self._up_frames + 1 if up else 0
            if self._up_frames * FRAME_S >= HOLD_S:
                reached = "held_up"
            else:
                reached = "lifted" if up else "grasped"
            if LiftBox.stages.index(reached) > LiftBox.stages.index(self.stage):
                self.stage = reached
        success = self.stage == "held_up"
        progress = LiftBox.stages.index(self.stage) / (len(LiftBox.stages) - 1)
        return Evaluation(success=success, failure=False, progress=progress, stage=self.stage)


class LiftBox(Task):
    name: ClassVar[str] = "lift_box"
    summary: ClassVar[str] = "lift a box off the conveyor with both hands and hold it up"
    stages: ClassVar[tuple[str, ...]] = ("none", "touched", "grasped", "lifted", "held_up")
    worlds: ClassVar[Mapping[WorldName, Mapping[str, float]]] = BoxTransfer.worlds
    goal_names: ClassVar[tuple[str, ...]] = ("lift_m",)

    def instruction(self, required: int) -> str:
        return "Lift the box off the conveyor and hold it up."

    def goal(self, conditions: Mapping[str, Any], world: WorldConfig) -> tuple[float, ...]:
        return (LIFT_M,)

    def scene(self) -> TaskScene:
        """Box transfer's: the feeder brings the boxes (none is delivered here: the trial
        ends once a box is held up)."""
        return BoxTransferScene(self.name)

    def new_trial(self, required: int) -> LiftJudge:
        return LiftJudge()

    def expert(self, config: ExpertConfig) -> Operator:
        """Box transfer's expert: it picks the box up and lifts it on its way to the table."""
        return ExpertOperator(config)

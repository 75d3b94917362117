"""Box transfer, the paper's task: boxes arrive on the conveyor; the robot picks each one
up with both hands, carries it to the delivery table and sets it down in the zone."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from types import MappingProxyType
from typing import Any, ClassVar

from workcell.expert.skill import ExpertConfig
from workcell.sim.config import WorldConfig
from workcell.sim.world import World
from workcell.task.operator import Operator
from workcell.tasks.box_transfer.judge import BoxTransferJudge
from workcell.tasks.box_transfer.scene import BoxTransferScene
from workcell.tasks.box_transfer.settled import DeliveriesStay
from workcell.tasks.box_transfer.stages import TASK_STAGES
from workcell.tasks.elements.expert import ExpertOperator
from workcell.tasks.task import Reference, Task
from workcell.tasks.worlds import WorldName, WorldRanges, shifted_worlds

ONE_BOX = "Carry the box from the conveyor to the delivery table."
BOXES = "Carry {n} boxes from the conveyor to the delivery table."


class BoxTransfer(Task):
    name: ClassVar[str] = "box_transfer"
    summary: ClassVar[str] = (
        "carry boxes from the conveyor to the delivery table, one at a time, with both hands"
    )
    stages: ClassVar[tuple[str, ...]] = TASK_STAGES
    worlds: ClassVar[Mapping[WorldName, WorldRanges]] = shifted_worlds(
        box_size=0.15,
        box_mass=0.3,
        box_colour=0.2,
        conveyor_speed=0.25,
        release_interval=0.25,
    )
    """D1 moves the robot's start and the delivery zone (the target) up to 0.1 m and turns
    the start up to 0.1 rad; D2 widens that to 0.3 and varies the boxes and the feed."""

    goal_names: ClassVar[tuple[str, ...]] = ("goal_x", "goal_y")
    """The delivery zone's centre in the world (m): where this trial's boxes go."""

    segment_references: ClassVar[Mapping[str, Reference]] = MappingProxyType(
        {
            "none": "box",
            "touched": "box",
            "grasped": "box",
            "lifted": "box",
            "over_zone": "goal",
            "delivered": "goal",
        }
    )
    """Up to the lift the arms act on the box (reaching, closing, lifting it), from then on
    on where it goes (carrying it over the zone, setting it down)."""

    def goal(self, conditions: Mapping[str, Any], world: WorldConfig) -> tuple[float, ...]:
        center = conditions.get("target_center")
        if not (isinstance(center, Sequence) and len(center) == 2):
            center = world.target.center
        return float(center[0]), float(center[1])

    def instruction(self, required: int) -> str:
        return ONE_BOX if required == 1 else BOXES.format(n=required)

    def scene(self) -> BoxTransferScene:
        return BoxTransferScene(self.name)

    def new_trial(self, required: int) -> BoxTransferJudge:
        return BoxTransferJudge(required)

    def expert(self, config: ExpertConfig) -> Operator:
        return ExpertOperator(config)

    def settled_check(self, world: World) -> DeliveriesStay:
        return DeliveriesStay(world)

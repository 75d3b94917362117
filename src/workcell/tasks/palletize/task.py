"""Palletize: four boxes arrive on the conveyor; the robot carries each, with both hands,
to the pallet beside the conveyor's end and sets it in the next free slot of a 2x2
pattern, until the pallet is full and at rest."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any, ClassVar

from workcell.expert.skill import ExpertConfig
from workcell.sim.config import WorldConfig
from workcell.sim.world import World
from workcell.task.operator import Operator
from workcell.tasks.box_transfer.task import BoxTransfer
from workcell.tasks.palletize.expert import PalletizeExpert
from workcell.tasks.palletize.judge import PalletizeJudge
from workcell.tasks.palletize.layout import PALLET_HEIGHT, SLOT_SIGNS, PalletLayout
from workcell.tasks.palletize.scene import PalletizeScene
from workcell.tasks.palletize.settled import SlotsStayFilled
from workcell.tasks.palletize.stages import PALLET_BOXES, PALLETIZE_STAGES
from workcell.tasks.task import BY_GRASP, GoalSite, SegmentReferences, Task
from workcell.tasks.worlds import WorldName, WorldRanges

PALLET_TIME_LIMIT_S = 180.0
"""Four carries: the expert takes 94-113 s (bench/expert_palletize.py), a person longer."""

INSTRUCTION = (
    "Stack the four boxes from the conveyor on the pallet, one in each slot of the 2x2 pattern."
)


class Palletize(Task):
    name: ClassVar[str] = "palletize"
    summary: ClassVar[str] = (
        "stack four boxes from the conveyor on a pallet in a 2x2 pattern, one at a time"
    )
    stages: ClassVar[tuple[str, ...]] = PALLETIZE_STAGES
    worlds: ClassVar[Mapping[WorldName, WorldRanges]] = BoxTransfer.worlds
    """Box transfer's: D1 moves the robot's start and the pallet (with the target shift) up
    to 0.1 m and turns them up to 0.1 rad; D2 widens that three times and varies the boxes'
    size (and so the slot layout), mass and colour, and the feed."""
    goal_names: ClassVar[tuple[str, ...]] = tuple(
        f"slot_{i + 1}_{axis}" for i in range(len(SLOT_SIGNS)) for axis in ("x", "y")
    )
    """The four slots' centres in the world (m), in the order the expert fills them."""

    def goal(self, conditions: Mapping[str, Any], world: WorldConfig) -> tuple[float, ...]:
        layout = PalletLayout.of(conditions, world)
        return tuple(float(v) for center in layout.slot_centers() for v in center)

    objects_per_trial: ClassVar[int | None] = PALLET_BOXES
    least_time_limit_s: ClassVar[float] = PALLET_TIME_LIMIT_S

    def instruction(self, required: int) -> str:
        """Every trial fills the pallet (the schedule's box count does not change it)."""
        return INSTRUCTION

    def scene(self) -> PalletizeScene:
        return PalletizeScene(self.name)

    def new_trial(self, required: int) -> PalletizeJudge:
        """A judge asking for the full pallet, whatever box count the schedule asks."""
        return PalletizeJudge(PALLET_BOXES)

    def expert(self, config: ExpertConfig) -> Operator:
        return PalletizeExpert(config)

    segment_references: ClassVar[SegmentReferences] = BY_GRASP
    """Four carries a trial: a segment ends where the hands take a box (it acts on that box)
    or let go of it (it acts on the slot the box was set down in)."""

    def goal_sites(self, goal: Sequence[float]) -> tuple[GoalSite, ...]:
        """The four slots, each turned with the pallet (whose +x runs from the first slot to
        the third: :data:`~workcell.tasks.palletize.layout.SLOT_SIGNS`), at its top."""
        centers = [(float(goal[2 * i]), float(goal[2 * i + 1])) for i in range(len(SLOT_SIGNS))]
        (x0, y0), (x2, y2) = centers[0], centers[2]
        yaw = math.atan2(y2 - y0, x2 - x0)
        return tuple(GoalSite(x, y, yaw, PALLET_HEIGHT) for x, y in centers)

    def settled_check(self, world: World) -> SlotsStayFilled:
        return SlotsStayFilled(world)

"""Sort: boxes of two kinds (a small and a large one, each of its own colour, drawn per
trial) arrive on the conveyor in random order; each kind goes to its own table, the
delivery table or the sorting table across the conveyor, whose zone wears the kind's
colour."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any, ClassVar

from workcell.expert.skill import ExpertConfig
from workcell.sim.config import WorldConfig
from workcell.sim.world import World
from workcell.task.operator import Operator
from workcell.tasks.sort.expert import SortExpert
from workcell.tasks.sort.judge import SortJudge
from workcell.tasks.sort.layout import SortLayout, sorting_table_center
from workcell.tasks.sort.scene import SortScene
from workcell.tasks.sort.settled import SortedStay
from workcell.tasks.sort.stages import SORT_STAGES
from workcell.tasks.task import BY_GRASP, GoalSite, ObjectLook, SegmentReferences, Task
from workcell.tasks.worlds import WorldName, WorldRanges, shifted_worlds

ONE_BOX = "Sort the box from the conveyor onto the table whose zone has its colour."
BOXES = "Sort {n} boxes from the conveyor: each onto the table whose zone has its colour."
MAX_BOXES = 12
SORTED_BOXES = 4
"""Boxes every trial sorts: two of each kind (the default pool of four)."""
"""The goal names a kind for this many pooled boxes (``feeder.pool_size``'s upper bound)."""
NO_BOX = -1.0
"""The goal's table for a pool index the trial's pool does not have."""


class Sort(Task):
    name: ClassVar[str] = "sort"
    summary: ClassVar[str] = (
        "sort boxes of two kinds from the conveyor, each kind onto its own table"
    )
    stages: ClassVar[tuple[str, ...]] = SORT_STAGES
    worlds: ClassVar[Mapping[WorldName, WorldRanges]] = shifted_worlds(
        box_size=0.15,
        box_mass=0.3,
        conveyor_speed=0.25,
        release_interval=0.25,
    )
    """The target is both tables: D1 moves them and the start up to 0.1 m; D2 widens that
    to 0.3 and varies the boxes' size and mass and the feed."""
    goal_names: ClassVar[tuple[str, ...]] = (
        "delivery_table_x",
        "delivery_table_y",
        "sorting_table_x",
        "sorting_table_y",
        *(f"box_{i}_table" for i in range(MAX_BOXES)),
    )
    """The two zones' centres in the world (m), then for each pooled box the table its kind
    goes to (0: the delivery table, 1: the sorting table; -1: no such box in the pool)."""

    def goal(self, conditions: Mapping[str, Any], world: WorldConfig) -> tuple[float, ...]:
        center = conditions.get("target_center")
        if not (isinstance(center, Sequence) and len(center) == 2):
            center = world.target.center
        values = conditions.get("task")
        if isinstance(values, Mapping) and "box_kinds" in values:
            layout = SortLayout.from_recorded(values, center)
            tables = layout.tables
            kinds = [float(k) for k in layout.box_kinds]
        else:  # conditions recorded without the trial's draw: the nominal tables
            tables = ((float(center[0]), float(center[1])), sorting_table_center(world))
            kinds = []
        kinds = (kinds + [NO_BOX] * MAX_BOXES)[:MAX_BOXES]
        return (*tables[0], *tables[1], *kinds)

    def object_looks(
        self, conditions: Mapping[str, Any], pool: int, trial_box: ObjectLook
    ) -> tuple[ObjectLook, ...]:
        """Each pooled box in its kind's size and colour, as the trial drew them."""
        values = conditions.get("task")
        if not (isinstance(values, Mapping) and "box_kinds" in values):
            return super().object_looks(conditions, pool, trial_box)
        center = conditions.get("target_center", (0.0, 0.0))  # (the looks need no table)
        layout = SortLayout.from_recorded(values, center)
        looks = [ObjectLook(kind.size, kind.rgba) for kind in layout.kinds]
        return tuple(
            looks[layout.box_kinds[i]] if i < len(layout.box_kinds) else trial_box
            for i in range(pool)
        )

    objects_per_trial: ClassVar[int | None] = SORTED_BOXES
    """Two boxes of each kind in every trial (the expert takes 62-76 s, bench/expert_sort.py)."""

    def instruction(self, required: int) -> str:
        return ONE_BOX if required == 1 else BOXES.format(n=required)

    def scene(self) -> SortScene:
        return SortScene(self.name)

    def new_trial(self, required: int) -> SortJudge:
        return SortJudge(required)

    segment_references: ClassVar[SegmentReferences] = BY_GRASP
    """Four carries a trial: a segment ends where the hands take a box (it acts on that box)
    or let go of it (it acts on the table it was set down on)."""

    def goal_sites(self, goal: Sequence[float]) -> tuple[GoalSite, ...]:
        """The delivery table's zone and the sorting table's (the kinds' tables 0 and 1)."""
        return (GoalSite(float(goal[0]), float(goal[1])), GoalSite(float(goal[2]), float(goal[3])))

    def source_key(self, goal: Sequence[float]) -> tuple[float, ...]:
        """Which table each pooled box goes to: a source's carries go to the tables an
        attempt's boxes need only when its boxes' kinds came in the same order."""
        return tuple(float(v) for v in goal[4:])

    def settled_check(self, world: World) -> SortedStay:
        return SortedStay(world)

    def expert(self, config: ExpertConfig) -> Operator:
        return SortExpert(config)

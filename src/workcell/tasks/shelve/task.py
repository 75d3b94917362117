"""Shelve: a box waits on the table; the robot puts it on the shelf the instruction names
(bottom, middle or top board), reaching up with its spine and arms for the top one."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from types import MappingProxyType
from typing import Any, ClassVar

from workcell.expert.skill import ExpertConfig
from workcell.sim.config import WorldConfig
from workcell.sim.world import World
from workcell.task.operator import Operator
from workcell.tasks.shelve.expert import ShelveExpert
from workcell.tasks.shelve.judge import ShelveJudge
from workcell.tasks.shelve.scene import ShelveScene
from workcell.tasks.shelve.settled import ShelvedBoxStays
from workcell.tasks.shelve.shelf import ShelfLayout
from workcell.tasks.shelve.stages import SHELVE_STAGES
from workcell.tasks.task import GoalSite, Reference, Task
from workcell.tasks.worlds import WorldName, WorldRanges, shifted_worlds

ASKED = "Put the box from the table on the {shelf} shelf."
ANY_SHELF = "Put the box from the table on the shelf asked for: the bottom, middle or top one."


class Shelve(Task):
    name: ClassVar[str] = "shelve"
    summary: ClassVar[str] = (
        "put a box from the table on the shelf the instruction names (bottom, middle or top)"
    )
    stages: ClassVar[tuple[str, ...]] = SHELVE_STAGES
    worlds: ClassVar[Mapping[WorldName, WorldRanges]] = shifted_worlds(
        box_size=0.15,
        box_mass=0.3,
        box_colour=0.2,
    )
    """The target is the table and the shelf: D1 moves them and the start up to 0.1 m; D2
    widens that to 0.3 and varies the box's size, mass and colour."""
    goal_names: ClassVar[tuple[str, ...]] = ("shelf_x", "shelf_y", "shelf_height")
    """The asked board's centre in the world and its top's height (m)."""

    segment_references: ClassVar[Mapping[str, Reference]] = MappingProxyType(
        {
            "none": "box",
            "touched": "box",
            "grasped": "box",
            "lifted": "box",
            "placed": "goal",
            "settled": "goal",
        }
    )
    """Up to the lift the arms act on the box on the table (reaching, closing, lifting it),
    from then on on the asked board (carrying the box there, setting it down)."""

    def goal(self, conditions: Mapping[str, Any], world: WorldConfig) -> tuple[float, ...]:
        layout = ShelfLayout.from_recorded(conditions.get("task"))
        x, y = layout.board_center(layout.asked)
        return float(x), float(y), layout.board_top(layout.asked)

    def instruction(self, required: int) -> str:
        return ANY_SHELF

    def trial_instruction(self, required: int, conditions: Mapping[str, Any]) -> str:
        layout = ShelfLayout.from_recorded(conditions.get("task"))
        return ASKED.format(shelf=layout.asked_name)

    def scene(self) -> ShelveScene:
        return ShelveScene(self.name)

    def new_trial(self, required: int) -> ShelveJudge:
        """One box per trial, whatever ``required`` says."""
        return ShelveJudge()

    def expert(self, config: ExpertConfig) -> Operator:
        return ShelveExpert(config)

    def goal_sites(self, goal: Sequence[float]) -> tuple[GoalSite, ...]:
        """The asked board's centre and the height of its top."""
        return (GoalSite(float(goal[0]), float(goal[1]), 0.0, float(goal[2])),)

    def source_key(self, goal: Sequence[float]) -> tuple[float, ...]:
        """The asked board's height: a carry to the top board is replayed from one."""
        return (round(float(goal[2]), 3),)

    def settled_check(self, world: World) -> ShelvedBoxStays:
        return ShelvedBoxStays(world)

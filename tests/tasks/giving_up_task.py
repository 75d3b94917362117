"""A task whose judge says failure: box transfer that gives up after its first second (20
frame instants at the default 20 Hz), as a task whose box fell where it cannot be reached
would."""

from __future__ import annotations

from dataclasses import replace
from typing import ClassVar

from workcell.sim.events import WorldEvent
from workcell.sim.world import World
from workcell.tasks.box_transfer.judge import BoxTransferJudge
from workcell.tasks.box_transfer.task import BoxTransfer
from workcell.tasks.task import Evaluation

GIVE_UP_AFTER = 20
"""Frame instants a trial is judged before its judge says failure."""


class GivingUpJudge:
    def __init__(self, required: int) -> None:
        self._judge = BoxTransferJudge(required)
        self._judged = 0

    @property
    def done(self) -> int:
        return self._judge.done

    def observe(self, event: WorldEvent) -> None:
        self._judge.observe(event)

    def evaluate(self, world: World) -> Evaluation:
        self._judged += 1
        evaluation = self._judge.evaluate(world)
        return replace(evaluation, failure=self._judged >= GIVE_UP_AFTER)


class GivingUpTransfer(BoxTransfer):
    name: ClassVar[str] = "giving_up_transfer"
    summary: ClassVar[str] = "box transfer that fails after one second"

    def new_trial(self, required: int) -> GivingUpJudge:  # type: ignore[override]
        return GivingUpJudge(required)


class StrayJudge(GivingUpJudge):
    def evaluate(self, world: World) -> Evaluation:
        return replace(super().evaluate(world), stage="somewhere")


class StrayStageTransfer(BoxTransfer):
    """A task whose judge names a stage its task does not declare (a task's bug)."""

    name: ClassVar[str] = "stray_stage_transfer"
    summary: ClassVar[str] = "box transfer whose judge names a stage it does not have"

    def new_trial(self, required: int) -> StrayJudge:  # type: ignore[override]
        return StrayJudge(required)

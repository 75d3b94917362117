"""What each stage's motion acts on: the object a segment is expressed relative to.

Box transfer's stages (``none > touched > grasped > lifted > over_zone > delivered``) split
in two: up to the lift the arms act on the box (reaching, closing, lifting it), from then
on on where it goes (carrying it over the zone, setting it down). A segment ending at one
of the first stages moves with the box's pose, one ending at the others with the delivery
zone's. A task whose stages are not box transfer's has no such map yet.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Literal

from workcell.generate.errors import GenerateError

Reference = Literal["box", "goal"]
"""``box``: the box the trial grasps; ``goal``: where the trial's boxes go."""

BOX_TRANSFER_REFERENCES: Mapping[str, Reference] = {
    "none": "box",
    "touched": "box",
    "grasped": "box",
    "lifted": "box",
    "over_zone": "goal",
    "delivered": "goal",
}
"""The object a box-transfer segment ending at each stage acts on."""


def references_for(task_name: str, stages: tuple[str, ...]) -> Mapping[str, Reference]:
    """The reference of a segment ending at each of the task's stages; a GenerateError for
    a task whose stages generation does not know."""
    if tuple(BOX_TRANSFER_REFERENCES) == stages:
        return BOX_TRANSFER_REFERENCES
    raise GenerateError(
        f"--task {task_name}: generation knows the stages of box transfer "
        f"({' > '.join(BOX_TRANSFER_REFERENCES)}) and tasks that keep them; {task_name}'s "
        f"are {' > '.join(stages)}"
    )

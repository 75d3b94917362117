"""How far a palletize trial got: its stages, in order (definition version 1).

``none``
    no gripper touched a box.
``touched``
    a gripper touched a box.
``grasped``
    both pads closed on a box (the grasp holds it).
``placed_1`` .. ``placed_4``
    that many of the pallet's slots held a box at rest, released, at one frame instant.
``settled``
    all four slots held a box at rest, released, for :data:`SETTLE_S` on end: the task
    done.
"""

from __future__ import annotations

from typing import Literal, get_args

PalletizeStage = Literal[
    "none", "touched", "grasped", "placed_1", "placed_2", "placed_3", "placed_4", "settled"
]
PALLETIZE_STAGES: tuple[PalletizeStage, ...] = get_args(PalletizeStage)
STAGES_VERSION = "1"
PALLET_BOXES = 4
"""A trial fills the pallet: four boxes, one in each slot."""
SETTLE_S = 1.0
"""How long the full pallet must stay at rest, released, for the trial to succeed."""


def stage_of(touched: bool, grasped: bool, most_placed: int, settled: bool) -> PalletizeStage:
    """The furthest stage, given what the trial has reached so far."""
    if settled:
        return "settled"
    if most_placed >= 1:
        return PALLETIZE_STAGES[2 + min(most_placed, PALLET_BOXES)]
    if grasped:
        return "grasped"
    return "touched" if touched else "none"

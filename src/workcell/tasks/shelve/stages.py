"""How far a shelve trial got: its stages, in order.

``none``
    no gripper touched the box.
``touched``
    a gripper touched the box.
``grasped``
    both pads closed on the box (the grasp holds it).
``lifted``
    the held box rose at least :data:`LIFT_M` above its height when the hold began.
``placed``
    the box rested on the asked board, released.
``settled``
    it stayed there, released and still, for :data:`SETTLE_S`: the task done.
"""

from __future__ import annotations

from typing import Literal, get_args

ShelveStage = Literal["none", "touched", "grasped", "lifted", "placed", "settled"]
SHELVE_STAGES: tuple[ShelveStage, ...] = get_args(ShelveStage)
LIFT_M = 0.05
"""How far above its height at the start of a hold the held box must rise to be lifted."""
SETTLE_S = 1.0
"""How long the box must rest on the asked board, released and still, to succeed."""
REST_SPEED = 0.05
"""A box slower than this (m/s) is at rest."""

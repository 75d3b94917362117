"""The scripted expert's phases, in the order it goes through them for each box."""

from __future__ import annotations

import enum


class ExpertPhase(enum.Enum):
    """Wait for a box to rest, drive to it, open the palms around it, squeeze, lift, back
    away, carry it to the table, lower it into the zone, let go, back off."""

    WAIT = "wait"
    APPROACH = "approach"
    PREGRASP = "pregrasp"
    GRASP = "grasp"
    LIFT = "lift"
    RETREAT = "retreat"
    CARRY = "carry"
    PLACE = "place"
    RELEASE = "release"
    BACKOFF = "backoff"

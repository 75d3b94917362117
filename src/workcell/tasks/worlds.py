"""A task's worlds: ``D0`` (narrow), ``D1`` (moderate), ``D2`` (broad).

A world is a set of randomization ranges (``world.randomization.*``, see
:mod:`workcell.sim.randomization`): how far each trial's start, target, objects and timing
may stray from the configured ones, drawn from the trial's seed and recorded with it.
``--world D1`` sets a task's ranges for D1; a session's world is read back from the ranges
it stored (:func:`world_of`), so a store written before worlds had names still says which
one it ran in, and ranges set by hand are ``custom``.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from typing import Literal, get_args

from workcell.sim.randomization import RandomizationConfig

WorldName = Literal["D0", "D1", "D2"]
WORLDS: tuple[WorldName, ...] = get_args(WorldName)
CUSTOM = "custom"
"""The world of ranges that match none of the task's named worlds."""

WorldRanges = Mapping[str, float]
"""Randomization settings (``RandomizationConfig`` field names) that differ from 0."""


def randomization(ranges: WorldRanges) -> RandomizationConfig:
    """The randomization section of a world."""
    return RandomizationConfig(**ranges)


def world_overrides(ranges: WorldRanges) -> dict[str, float]:
    """Every ``world.randomization.*`` setting of a world, as dotted keys (those the world
    leaves at 0 included, so that it replaces whatever ranges were set before)."""
    section = randomization(ranges)
    return {
        f"world.randomization.{field.name}": getattr(section, field.name)
        for field in dataclasses.fields(section)
    }


def world_of(worlds: Mapping[WorldName, WorldRanges], section: RandomizationConfig) -> str:
    """The name of the world whose ranges ``section`` holds, or ``custom``."""
    for name in WORLDS:
        if randomization(worlds[name]) == section:
            return name
    return CUSTOM


NEAR = 0.1
"""D1's shift (m) of the start and the target and turn (rad) of the start: the shifted
worlds of ``bench/learn.py``."""
BROAD = 0.3
"""D2's: three times D1's."""


def shifted_worlds(**broad: float) -> dict[WorldName, WorldRanges]:
    """The worlds most tasks have: D0 as configured; D1 moves the robot's start and the
    task's target up to :data:`NEAR` m and turns the start up to :data:`NEAR` rad; D2 widens
    those to :data:`BROAD` and adds ``broad`` (the objects' size, mass, colour, the feed)."""
    near = {"start_shift": NEAR, "target_shift": NEAR, "start_yaw": NEAR}
    return {
        "D0": {},
        "D1": near,
        "D2": {**dict.fromkeys(near, BROAD), **broad},
    }

"""Typed events the world emits as boxes move through the task.

``t_sim`` is the world's clock here. The task layer stamps each of them with its trial
(:mod:`workcell.task.events` extends these classes, adding the trial index and putting
``t_sim`` on the trial clock), so the fields of a box event are declared only here.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class BoxReleased:
    """The feeder put a box on the belt start."""

    t_sim: float
    box: int


@dataclass(frozen=True)
class GraspChanged:
    """Both pads closed on a box (``engaged``) or let go of it."""

    t_sim: float
    box: int
    engaged: bool


@dataclass(frozen=True)
class BoxCompleted:
    """A released box came to rest where the trial's task wants it: the task's scene says
    where and when (box transfer's target zone, a pallet slot, its kind's table); the task
    layer stamps and records it (:mod:`workcell.task.events`)."""

    t_sim: float
    box: int


WorldEvent = BoxReleased | GraspChanged | BoxCompleted

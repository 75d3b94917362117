"""The paper's score: box score x boxes done + the remaining seconds, rounded up.

The remaining seconds are a time bonus a trial earns only by succeeding: a timed-out or
interrupted trial keeps its box points alone (:meth:`workcell.task.runner.SessionRunner`).
"""

from __future__ import annotations

import math

REMAINING_DECIMALS = 9
"""Remaining time is rounded to this many decimals before the ceiling, so that clock
arithmetic like 120 - 100.00000000001 does not gain a second."""


def time_bonus(time_limit_s: float, elapsed_s: float) -> int:
    """The seconds left of the trial's limit, rounded up: what a success now adds."""
    return math.ceil(max(0.0, round(time_limit_s - elapsed_s, REMAINING_DECIMALS)))


def trial_score(box_score: int, boxes_done: int, time_limit_s: float, elapsed_s: float) -> int:
    """Score of one trial (a level attempt) that succeeded after ``elapsed_s``: its box
    points (``boxes_done``: the boxes its task counts as done)
    and its time bonus."""
    return box_score * boxes_done + time_bonus(time_limit_s, elapsed_s)

"""The paper's score: box score x boxes delivered + the remaining seconds, rounded up."""

from __future__ import annotations

import math

REMAINING_DECIMALS = 9
"""Remaining time is rounded to this many decimals before the ceiling, so that clock
arithmetic like 120 - 100.00000000001 does not gain a second."""


def trial_score(box_score: int, boxes_delivered: int, time_limit_s: float, elapsed_s: float) -> int:
    """Score of one trial (a level attempt); a timed-out trial keeps its box points."""
    remaining = max(0.0, round(time_limit_s - elapsed_s, REMAINING_DECIMALS))
    return box_score * boxes_delivered + math.ceil(remaining)

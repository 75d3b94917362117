"""What the operator sees of a running session: the HUD, one type for the task and the wire.

:meth:`~workcell.task.runner.SessionRunner.hud` builds it and the server sends it inside
each ``State`` message unchanged, so the TypeScript ``Hud`` in ``web/src/protocol.ts`` is
generated from this class.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass

from workcell.session.config import Mode


class HudPhase(enum.Enum):
    """Where the session's current trial is (``finished`` once the session is over)."""

    COUNTDOWN = "countdown"
    RUNNING = "running"
    FINISHED = "finished"


@dataclass(frozen=True)
class Hud:
    """What the operator sees: mode, progress, clock and score; ``task`` is the session's
    task and ``stage`` the furthest of its stages the trial has reached (its judge's word
    at the latest frame instant: :mod:`workcell.tasks`)."""

    phase: HudPhase
    mode: Mode
    trial_index: int
    round: int | None
    rounds: int | None
    level: int | None
    boxes_delivered: int
    required_boxes: int
    countdown_s: float
    remaining_s: float
    score: int
    """The points the trial has earned so far: box score x boxes delivered, what it ends
    with unless it succeeds (a timeout or an interruption keeps them alone)."""
    task: str
    stage: str
    time_bonus: int
    """What a success now would add to ``score``: the seconds left, rounded up
    (:func:`workcell.task.scoring.time_bonus`); 0 outside a running trial."""
    instruction: str
    """What the trial asks, in one sentence: its task's
    :meth:`~workcell.tasks.task.Task.trial_instruction` (the shelf shelve asks for, say),
    the sentence every exported episode carries; empty before the first trial."""
    driver: str = "person"
    """Who drives the session (its ``driver`` setting): ``person``, ``expert`` or
    ``policy:<id>``."""
    taken_over: bool = False
    """The person has taken control from an autonomous ``driver`` (until they hand it
    back); always False when the driver is the person."""

"""Typed task events: every transition of a session, published to subscribers.

``t_sim`` is trial time (0 when the trial's clock starts; negative during the countdown).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

Outcome = Literal["success", "timeout", "interrupted"]
InterruptionReason = Literal[
    "operator_stop", "application_quit", "client_lost", "crash_recovered", "storage_error"
]


@dataclass(frozen=True)
class CountdownStarted:
    trial_index: int
    t_sim: float
    seconds: float


@dataclass(frozen=True)
class TrialStarted:
    trial_index: int
    t_sim: float
    mode: str
    round: int | None
    level: int | None
    required_boxes: int
    time_limit_s: float
    trial_seed: int
    conditions: dict[str, object]
    """The trial's box, belt, feed, target and start conditions (randomized or not)."""


@dataclass(frozen=True)
class BoxReleased:
    trial_index: int
    t_sim: float
    box: int


@dataclass(frozen=True)
class GraspChanged:
    trial_index: int
    t_sim: float
    box: int
    engaged: bool


@dataclass(frozen=True)
class BoxDelivered:
    trial_index: int
    t_sim: float
    box: int
    boxes_delivered: int


@dataclass(frozen=True)
class LevelChanged:
    """The campaign moves to another level (after a success) or repeats it (timeout)."""

    trial_index: int
    t_sim: float
    round: int
    level: int
    repeat: bool


@dataclass(frozen=True)
class TrialTimedOut:
    trial_index: int
    t_sim: float


@dataclass(frozen=True)
class TrialInterrupted:
    trial_index: int
    t_sim: float
    reason: InterruptionReason


@dataclass(frozen=True)
class TrialEnded:
    trial_index: int
    t_sim: float
    outcome: Outcome
    interruption_reason: InterruptionReason | None
    elapsed_s: float
    boxes_delivered: int
    score: int


TaskEvent = (
    CountdownStarted
    | TrialStarted
    | BoxReleased
    | GraspChanged
    | BoxDelivered
    | LevelChanged
    | TrialTimedOut
    | TrialInterrupted
    | TrialEnded
)


def event_kind(event: TaskEvent) -> str:
    """The stored name of an event type: ``trial_started``, ``box_delivered``, ..."""
    name = type(event).__name__
    return "".join("_" + c.lower() if c.isupper() else c for c in name).lstrip("_")

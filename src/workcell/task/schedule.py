"""Which trial comes next in each mode.

practice: one trial with one box. collection: one-box trials until N (0 = until stopped),
from trial index ``task.first_trial`` (a resumed study step; 0 by default).
challenge: R rounds of the configured levels; a success advances to the next level (after
the last level, the next round), a timeout repeats the level, and the campaign ends after
the last level of the last round. An interruption ends the session in every mode.
"""

from __future__ import annotations

from dataclasses import dataclass

from workcell.session.config import Mode, TaskConfig
from workcell.task.events import Outcome


@dataclass(frozen=True)
class TrialSpec:
    """What one trial asks for. ``round`` and ``level`` (1-based) are None outside challenge."""

    trial_index: int
    mode: Mode
    round: int | None
    level: int | None
    required_boxes: int
    time_limit_s: float


class Schedule:
    """Turns the task configuration and each outcome into the next trial."""

    def __init__(self, task: TaskConfig) -> None:
        self.task = task

    def first(self) -> TrialSpec:
        if self.task.mode == "challenge":
            return self._level(0, 1, 1)
        first = self.task.first_trial if self.task.mode == "collection" else 0
        return TrialSpec(first, self.task.mode, None, None, 1, self.task.time_limit_s)

    def next(self, spec: TrialSpec, outcome: Outcome) -> TrialSpec | None:
        """The trial after ``spec`` ended with ``outcome``; None when the session is over."""
        task, index = self.task, spec.trial_index + 1
        if outcome == "interrupted" or task.mode == "practice":
            return None
        if task.mode == "collection":
            if task.trials and index >= task.trials:
                return None
            return TrialSpec(index, "collection", None, None, 1, task.time_limit_s)
        assert spec.round is not None and spec.level is not None
        if outcome in ("timeout", "failed"):  # the level is repeated
            return self._level(index, spec.round, spec.level)
        if spec.level < task.levels:
            return self._level(index, spec.round, spec.level + 1)
        if spec.round < task.rounds:
            return self._level(index, spec.round + 1, 1)
        return None

    def completes(self, spec: TrialSpec, outcome: Outcome) -> bool:
        """Whether ``spec`` ending with ``outcome`` completes a challenge campaign: a
        success at the last level of the last round."""
        return (
            self.task.mode == "challenge"
            and outcome == "success"
            and spec.round == self.task.rounds
            and spec.level == self.task.levels
        )

    def _level(self, index: int, round_: int, level: int) -> TrialSpec:
        return TrialSpec(
            trial_index=index,
            mode="challenge",
            round=round_,
            level=level,
            required_boxes=self.task.level_boxes[level - 1],
            time_limit_s=self.task.level_time_limits_s[level - 1],
        )

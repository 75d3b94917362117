"""Every setup parameter of a session (the paper's Fig. 3), frozen and validated.

Defaults are the paper's. A session stores its whole :class:`SessionConfig` as metadata,
so every trial can be traced to the exact parameters it ran under.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal, get_args

from workcell import checks
from workcell.errors import ConfigError
from workcell.settings import section, setting
from workcell.sim.config import WorldConfig

Mode = Literal["practice", "collection", "challenge"]
MODES: tuple[str, ...] = get_args(Mode)


def _raise_if(problems: list[str]) -> None:
    if problems:
        raise ConfigError(problems)


def _positive_int(field: str, value: object, high: int) -> list[str]:
    if type(value) is not int or not 1 <= value <= high:
        return [checks.problem(field, value, f"must be a whole number from 1 to {high}")]
    return []


@dataclass(frozen=True)
class TaskConfig:
    """What the operator is asked to do: the mode and its levels, limits and scoring."""

    mode: Mode = setting(
        "practice",
        "practice (one trial, one box), collection (repeated one-box trials) or challenge "
        "(rounds of levels)",
    )
    time_limit_s: float = setting(
        120.0, "time limit of a practice or collection trial, s (> 0, at most 3600)"
    )
    trials: int = setting(
        0, "collection: stop after this many trials (0 = until stopped; at most 100000)"
    )
    rounds: int = setting(5, "challenge: rounds in the campaign (1 to 100)")
    box_score: int = setting(100, "points per delivered box (0 to 100000)")
    level_boxes: tuple[int, ...] = setting(
        (1, 2, 3), "challenge: boxes required at each level of a round (1 to 20 each)"
    )
    level_time_limits_s: tuple[float, ...] = setting(
        (120.0, 100.0, 90.0), "challenge: time limit of each level, s (> 0, at most 3600 each)"
    )
    countdown_s: float = setting(3.0, "countdown before each trial's clock starts, s (0 to 30)")

    def __post_init__(self) -> None:
        problems = checks.one_of("task.mode", self.mode, MODES)
        problems += _limit("task.time_limit_s", self.time_limit_s)
        if type(self.trials) is not int or not 0 <= self.trials <= 100_000:
            problems.append(
                checks.problem(
                    "task.trials", self.trials, "must be a whole number from 0 to 100000"
                )
            )
        problems += _positive_int("task.rounds", self.rounds, 100)
        if type(self.box_score) is not int or not 0 <= self.box_score <= 100_000:
            problems.append(
                checks.problem(
                    "task.box_score", self.box_score, "must be a whole number 0 to 100000"
                )
            )
        if not self.level_boxes:
            problems.append(checks.problem("task.level_boxes", (), "must list at least one level"))
        for i, boxes in enumerate(self.level_boxes):
            problems += _positive_int(f"task.level_boxes[{i}]", boxes, 20)
        for i, limit in enumerate(self.level_time_limits_s):
            problems += _limit(f"task.level_time_limits_s[{i}]", limit)
        if len(self.level_time_limits_s) != len(self.level_boxes):
            problems.append(
                checks.problem(
                    "task.level_time_limits_s",
                    tuple(self.level_time_limits_s),
                    f"must have one limit per level: task.level_boxes has "
                    f"{len(self.level_boxes)} levels",
                )
            )
        problems += checks.in_range("task.countdown_s", self.countdown_s, 0.0, 30.0, "s")
        _raise_if(problems)

    @property
    def levels(self) -> int:
        return len(self.level_boxes)


def _limit(field: str, value: float) -> list[str]:
    if not (isinstance(value, int | float) and math.isfinite(value) and 0 < value <= 3600):
        return [checks.problem(field, value, "must be > 0 and at most 3600 s")]
    return []


@dataclass(frozen=True)
class RecordingConfig:
    """How frames are sampled and which motion counts as activity in the metrics."""

    sampling_rate_hz: float = setting(
        20.0, "frames per second of simulated time (> 0, dividing the physics rate evenly)"
    )
    grip_threshold: float = setting(
        0.5, "a grip value at or above this engages arm following (0 to 1, exclusive of 0)"
    )
    base_linear_threshold: float = setting(
        0.02, "base speed above which the base counts as moving, m/s (> 0, at most 1)"
    )
    base_yaw_threshold: float = setting(
        0.05, "base turn rate above which the base counts as moving, rad/s (> 0, at most 1)"
    )
    joint_rate_threshold: float = setting(
        0.05, "arm joint speed above which an arm counts as moving, rad/s (> 0, at most 1)"
    )

    def __post_init__(self) -> None:
        problems = checks.positive("recording.sampling_rate_hz", self.sampling_rate_hz, "Hz")
        if not (math.isfinite(self.grip_threshold) and 0.0 < self.grip_threshold <= 1.0):
            problems.append(
                checks.problem(
                    "recording.grip_threshold", self.grip_threshold, "must be > 0 and at most 1"
                )
            )
        for name in ("base_linear_threshold", "base_yaw_threshold", "joint_rate_threshold"):
            value = getattr(self, name)
            if not (math.isfinite(value) and 0.0 < value <= 1.0):
                problems.append(
                    checks.problem(f"recording.{name}", value, "must be > 0 and at most 1")
                )
        _raise_if(problems)


@dataclass(frozen=True)
class SessionConfig:
    """One operator sitting: task, recording, world, seed and operator."""

    task: TaskConfig = section(TaskConfig, "the task mode, levels, limits and scoring")
    recording: RecordingConfig = section(RecordingConfig, "sampling and activity thresholds")
    world: WorldConfig = section(WorldConfig, "the factory workcell and the robot")
    seed: int = setting(0, "session seed: every trial's start is derived from it (0 to 2^63)")
    operator_id: str = setting(
        "anonymous", "who operates (letters, digits, '.', '_', '-'; 1 to 64 characters)"
    )

    def __post_init__(self) -> None:
        problems: list[str] = []
        if type(self.seed) is not int or not 0 <= self.seed < 2**63:
            problems.append(checks.problem("seed", self.seed, "must be a whole number 0 to 2^63-1"))
        valid_id = (
            isinstance(self.operator_id, str)
            and 1 <= len(self.operator_id) <= 64
            and all(c.isalnum() or c in "._-" for c in self.operator_id)
        )
        if not valid_id:
            problems.append(
                checks.problem(
                    "operator_id",
                    self.operator_id,
                    "must be 1 to 64 letters, digits, '.', '_' or '-'",
                )
            )
        physics_hz = 1.0 / self.world.timestep
        rate = self.recording.sampling_rate_hz
        per_frame = physics_hz / rate
        if rate > physics_hz + 1e-9 or abs(per_frame - round(per_frame)) > 1e-6:
            problems.append(
                checks.problem(
                    "recording.sampling_rate_hz",
                    rate,
                    f"must divide the physics rate ({physics_hz:g} Hz = 1 / world.timestep) "
                    "into a whole number of steps, e.g. 10, 20, 40 or 50",
                )
            )
        _raise_if(problems)

    @property
    def physics_steps_per_frame(self) -> int:
        return round(1.0 / (self.world.timestep * self.recording.sampling_rate_hz))

"""What the store is given (session info, trial start and end) and what it returns (rows).

Frozen dataclasses, checked on construction: a bad value raises :class:`RecordError`
naming the field. Times are Unix seconds (``*_wall``) or sim seconds (``t_sim``).
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping
from dataclasses import dataclass, field, fields
from typing import Any, Protocol

from workcell import __version__
from workcell.record.columns import INTERRUPTION_REASONS, OUTCOMES
from workcell.record.errors import RecordError
from workcell.sim.joints import JOINT_ORDER


class MetricValues(Protocol):
    """The stored metrics' attributes, as :class:`workcell.metrics.TrialMetrics` has them."""

    @property
    def path_length_m(self) -> float: ...
    @property
    def smoothness(self) -> float: ...
    @property
    def active_ratio(self) -> float: ...
    @property
    def hz_wall(self) -> float: ...
    @property
    def hz_sim(self) -> float: ...
    @property
    def max_gap_s(self) -> float: ...


FLAG_SEPARATOR = ";"
"""``quality_flags`` are stored as one text, flags joined by ';' (NULL when none)."""


def to_json(value: object, where: str) -> str:
    """Canonical JSON text (sorted keys, no NaN/inf) of a parameter-like value."""
    try:
        return json.dumps(value, sort_keys=True, separators=(",", ":"), allow_nan=False)
    except (TypeError, ValueError) as error:
        raise RecordError(f"{where}: cannot be stored as JSON ({error})") from None


def _nonempty(value: str, where: str) -> None:
    if not isinstance(value, str) or not value:
        raise RecordError(f"{where}: must be a non-empty text, got {value!r}")


@dataclass(frozen=True)
class SessionInfo:
    """What a session records once, at its start: every parameter and definition."""

    mode: str
    operator_id: str
    seed: int
    parameters: Mapping[str, Any]
    thresholds: Mapping[str, float]
    metric_definitions: Mapping[str, Any]
    metrics_version: str
    joint_order: tuple[str, ...] = JOINT_ORDER
    software_version: str = __version__

    def __post_init__(self) -> None:
        for name in ("mode", "operator_id", "metrics_version", "software_version"):
            _nonempty(getattr(self, name), f"session {name}")
        for name in ("parameters", "thresholds", "metric_definitions"):
            to_json(getattr(self, name), f"session {name}")
        if tuple(self.joint_order) != JOINT_ORDER:
            raise RecordError(
                f"session joint_order {list(self.joint_order)} is not the frame columns' "
                f"order {list(JOINT_ORDER)} (workcell.sim.joints.JOINT_ORDER)"
            )


@dataclass(frozen=True)
class TrialStart:
    """What a trial records at its start. ``round``/``level`` are None outside challenge;
    ``task`` (``task.kind``), ``world`` (D0, D1, D2) and ``goal`` (the task's goal numbers
    by name) None where not known (stored as NULL)."""

    mode: str
    required_boxes: int
    time_limit_s: float
    round: int | None = None
    level: int | None = None
    trial_seed: int | None = None
    task: str | None = None
    world: str | None = None
    goal: Mapping[str, float] | None = None
    driver: str | None = None
    """Who drives (schema version 6): ``person``, ``expert``, ``policy:<id>``,
    ``generated``; None where not known."""

    def __post_init__(self) -> None:
        _nonempty(self.mode, "trial mode")
        if not (math.isfinite(self.time_limit_s) and self.time_limit_s > 0):
            raise RecordError(f"trial time_limit_s = {self.time_limit_s}: must be > 0")
        for name in ("task", "world", "driver"):
            value = getattr(self, name)
            if value is not None:
                _nonempty(value, f"trial {name}")
        if self.goal is not None:
            to_json(self.goal, "trial goal")

    def task_columns(self) -> dict[str, object]:
        """The trial row's task columns written at its start."""
        return {
            "task": self.task,
            "world": self.world,
            "goal_json": None if self.goal is None else to_json(self.goal, "trial goal"),
            "driver": self.driver,
        }


@dataclass(frozen=True)
class StoredMetrics:
    """The derived metrics a trial row keeps (the trials.csv metric columns); NaN (stored
    as NULL) when undefined or not computed. :func:`workcell.metrics.compute_trial_metrics`
    computes them; :meth:`of` takes its result."""

    path_length_m: float = math.nan
    smoothness: float = math.nan
    active_ratio: float = math.nan
    hz_wall: float = math.nan
    hz_sim: float = math.nan
    max_gap_s: float = math.nan

    @classmethod
    def of(cls, computed: MetricValues) -> StoredMetrics:
        return cls(
            path_length_m=computed.path_length_m,
            smoothness=computed.smoothness,
            active_ratio=computed.active_ratio,
            hz_wall=computed.hz_wall,
            hz_sim=computed.hz_sim,
            max_gap_s=computed.max_gap_s,
        )


@dataclass(frozen=True)
class TrialEnd:
    """How a trial ended. Outcome, inclusion and quality flags are independent."""

    outcome: str
    elapsed_s: float
    boxes_delivered: int
    score: int
    interruption_reason: str | None = None
    completion_time_s: float | None = None
    metrics: StoredMetrics = field(default_factory=StoredMetrics)
    quality_flags: tuple[str, ...] = ()
    included: bool = True
    exclusion_reason: str | None = None
    stage: str | None = None
    """The furthest of the task's stages reached, as its judge said last (None: unknown)."""
    progress: float | None = None
    """The task's progress (0..1) as its judge said last (None: unknown)."""

    def __post_init__(self) -> None:
        if self.stage is not None:
            _nonempty(self.stage, "trial stage")
        if self.progress is not None and not 0.0 <= self.progress <= 1.0:
            raise RecordError(f"trial progress = {self.progress}: must be 0 to 1")
        if self.outcome not in OUTCOMES:
            raise RecordError(f"trial outcome {self.outcome!r}: must be one of {OUTCOMES}")
        interrupted = self.outcome == "interrupted"
        if interrupted and self.interruption_reason not in INTERRUPTION_REASONS:
            raise RecordError(
                f"interruption_reason {self.interruption_reason!r}: an interrupted trial "
                f"needs one of {INTERRUPTION_REASONS}"
            )
        if not interrupted and self.interruption_reason is not None:
            raise RecordError(f"interruption_reason given for a {self.outcome} trial")
        for flag in self.quality_flags:
            if not flag or FLAG_SEPARATOR in flag:
                raise RecordError(f"quality flag {flag!r}: must be non-empty, without ';'")
        if self.included and self.exclusion_reason is not None:
            raise RecordError("exclusion_reason given for an included trial")


@dataclass(frozen=True)
class SessionRecord:
    session_id: str
    created_wall: float
    ended_wall: float | None
    schema_version: int
    software_version: str
    mode: str
    operator_id: str
    seed: int
    parameters: dict[str, Any]
    thresholds: dict[str, Any]
    joint_order: tuple[str, ...]
    metric_definitions: dict[str, Any]
    metrics_version: str
    status: str

    @classmethod
    def from_row(cls, row: Mapping[str, Any]) -> SessionRecord:
        return cls(
            session_id=row["session_id"],
            created_wall=row["created_wall"],
            ended_wall=row["ended_wall"],
            schema_version=row["schema_version"],
            software_version=row["software_version"],
            mode=row["mode"],
            operator_id=row["operator_id"],
            seed=row["seed"],
            parameters=json.loads(row["parameters_json"]),
            thresholds=json.loads(row["thresholds_json"]),
            joint_order=tuple(json.loads(row["joint_order_json"])),
            metric_definitions=json.loads(row["metric_definitions_json"]),
            metrics_version=row["metrics_version"],
            status=row["status"],
        )


def _real(value: float | None) -> float:
    return math.nan if value is None else value


_DERIVED = ("metrics", "quality_flags", "included", "goal")
"""TrialRecord fields not read verbatim from their column of the same name."""


@dataclass(frozen=True)
class TrialRecord:
    """A trial row. ``outcome`` is None while the trial runs; metrics NaN when undefined."""

    session_id: str
    trial_id: str
    trial_index: int
    mode: str
    round: int | None
    level: int | None
    required_boxes: int
    time_limit_s: float
    outcome: str | None
    interruption_reason: str | None
    elapsed_s: float | None
    completion_time_s: float | None
    boxes_delivered: int | None
    score: int | None
    n_frames: int | None
    metrics: StoredMetrics
    quality_flags: tuple[str, ...]
    included: bool | None
    exclusion_reason: str | None
    trial_seed: int | None
    started_wall: float
    ended_wall: float | None
    task: str | None = None
    """The task columns (schema version 5; None in trials recorded before it)."""
    world: str | None = None
    stage: str | None = None
    progress: float | None = None
    goal: dict[str, Any] | None = None
    driver: str | None = None
    """Who drove (schema version 6; None in trials recorded before it)."""

    @classmethod
    def from_row(cls, row: Mapping[str, Any]) -> TrialRecord:
        flags = row["quality_flags"]
        included = row["included"]
        plain = {f.name: row[f.name] for f in fields(cls) if f.name not in _DERIVED}
        goal = row["goal_json"]
        return cls(
            **plain,
            goal=None if goal is None else json.loads(goal),
            metrics=StoredMetrics(**{f.name: _real(row[f.name]) for f in fields(StoredMetrics)}),
            quality_flags=tuple(flags.split(FLAG_SEPARATOR)) if flags else (),
            included=None if included is None else bool(included),
        )


@dataclass(frozen=True)
class EventRecord:
    event_id: str
    session_id: str
    trial_id: str | None
    seq: int
    t_sim: float | None
    t_wall: float
    kind: str
    payload: dict[str, Any]

    @classmethod
    def from_row(cls, row: Mapping[str, Any]) -> EventRecord:
        return cls(
            event_id=row["event_id"],
            session_id=row["session_id"],
            trial_id=row["trial_id"],
            seq=row["seq"],
            t_sim=row["t_sim"],
            t_wall=row["t_wall"],
            kind=row["kind"],
            payload=json.loads(row["payload_json"]),
        )


@dataclass(frozen=True)
class AnnotationRecord:
    """A reviewer's decision on a trial: ``kind`` include, exclude or note."""

    annotation_id: str
    trial_id: str
    kind: str
    reason: str
    by: str
    at_wall: float

    @classmethod
    def from_row(cls, row: Mapping[str, Any]) -> AnnotationRecord:
        return cls(**{name: row[name] for name in cls.__dataclass_fields__})


@dataclass(frozen=True)
class StoreCounts:
    sessions: int
    trials: int
    events: int
    frames: int
    annotations: int

"""What the audit reads besides frames: sessions, trials and reviewer annotations.

The same rows come from a store or from a CSV export, so both audits see identical values.
Trials keep exactly the interchange contract's trial columns as stored (``stored``); the
audit recomputes the derived ones from frames and never writes them back.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

from workcell.audit.task_stages import FRAMES_TASK, Zone, session_task, session_zone
from workcell.errors import ConfigError
from workcell.metrics import MetricThresholds
from workcell.record.columns import TRIAL_COLUMNS
from workcell.record.entries import FLAG_SEPARATOR
from workcell.record.study_tags import StudyTags
from workcell.session.config import RecordingConfig


def recorded_rate(parameters: Mapping[str, Any]) -> tuple[float, str | None]:
    """The frame rate a session's ``parameters`` state, validated by its declaration in
    :class:`RecordingConfig`; else the declared default and a note saying why."""
    recording = parameters.get("recording")
    rate = recording.get("sampling_rate_hz") if isinstance(recording, Mapping) else None
    default = RecordingConfig().sampling_rate_hz
    if rate is None:
        return default, f"parameters hold no recording.sampling_rate_hz; {default:g} Hz was assumed"
    try:
        return RecordingConfig(sampling_rate_hz=rate).sampling_rate_hz, None
    except ConfigError as error:
        return default, f"{error}; {default:g} Hz was assumed"


@dataclass(frozen=True)
class SessionRow:
    """One session as the audit needs it. ``notes`` say where defaults replaced values the
    session row did not hold in a readable form."""

    session_id: str
    created_wall: float
    mode: str
    operator_id: str
    metrics_version: str
    thresholds: MetricThresholds
    rate_hz: float
    notes: tuple[str, ...] = ()
    condition: str = ""
    """The session's study condition (setting ``condition``; empty: none)."""
    study_step: int | None = None
    """Which of the participant's planned sessions it was (None: not known)."""
    task: str = FRAMES_TASK
    """The ``task.kind`` the session's parameters name (box transfer before tasks had
    names)."""
    zone: Zone = field(default_factory=lambda: session_zone({}))
    """The target zone the session's world configures (trials may move its centre)."""
    seed: int | None = None
    """The session seed (None: not read)."""
    status: str = ""
    """``completed``, ``interrupted``, ... (:data:`workcell.record.columns.SESSION_STATUSES`)."""
    driver: str = "person"
    """The session's ``driver`` setting: ``person`` unless a live session's autonomous
    driver drove while its operator watched (``workcell collect`` records ``person``: its
    ``--operator`` drove, and nobody watched)."""

    @classmethod
    def parse(
        cls,
        row: Mapping[str, Any],
        parameters: Mapping[str, Any],
        thresholds: Mapping[str, Any],
    ) -> SessionRow:
        """From a sessions row (``session_id``, ``created_wall``, ``mode``, ``operator_id``,
        ``metrics_version``; ``seed`` and ``status`` where it has them) and its decoded
        ``parameters`` and ``thresholds`` JSON."""
        notes: list[str] = []
        try:
            metric_thresholds = MetricThresholds.from_stored(thresholds)
        except (ValueError, TypeError) as error:
            metric_thresholds = MetricThresholds()
            notes.append(
                f"thresholds not readable ({error}); the defaults of docs/architecture.md were used"
            )
        rate, note = recorded_rate(parameters)
        if note is not None:
            notes.append(note)
        tags = StudyTags.of(row["operator_id"], parameters)
        return cls(
            session_id=row["session_id"],
            created_wall=float(row["created_wall"]),
            mode=row["mode"],
            operator_id=row["operator_id"],
            metrics_version=row["metrics_version"],
            thresholds=metric_thresholds,
            rate_hz=float(rate),
            notes=tuple(notes),
            condition=tags.condition or "",
            study_step=tags.study_step,
            task=session_task(parameters),
            zone=session_zone(parameters),
            seed=None if row.get("seed") is None else int(row["seed"]),
            status=str(row.get("status") or ""),
            driver=str(parameters.get("driver") or "person"),
        )


@dataclass(frozen=True)
class TrialRow:
    """One trial's contract columns as stored (``stored``: every name of TRIAL_COLUMNS,
    NULL as None), with the ones the audit reasons about as typed fields."""

    session_id: str
    trial_id: str
    trial_index: int
    mode: str
    level: int | None
    outcome: str | None
    interruption_reason: str | None
    stored: Mapping[str, Any]
    task: str | None = None
    """The trial's task as recorded (schema version 5; None before it)."""
    recorded_stage: str | None = None
    """The furthest stage its task's judge said the trial reached (schema version 5; None
    before it, and in a trial never closed)."""
    world: str | None = None
    """The named world (``D0``, ``D1``, ``D2``) the trial ran in (schema version 5; None
    before it and for ranges of no named world)."""
    driver: str | None = None
    """Who drove (``person``, ``expert``, ``policy:<id>``, ``generated``; schema version 6,
    None before it)."""

    @classmethod
    def parse(cls, row: Mapping[str, Any]) -> TrialRow:
        stored = {name: row[name] for name in TRIAL_COLUMNS}
        task, stage, world = row.get("task"), row.get("stage"), row.get("world")
        driver = row.get("driver")
        return cls(
            session_id=stored["session_id"],
            trial_id=stored["trial_id"],
            trial_index=int(stored["trial_index"]),
            mode=stored["mode"],
            level=stored["level"],
            outcome=stored["outcome"],
            interruption_reason=stored["interruption_reason"],
            stored=stored,
            task=task if isinstance(task, str) and task else None,
            recorded_stage=stage if isinstance(stage, str) and stage else None,
            world=world if isinstance(world, str) and world else None,
            driver=driver if isinstance(driver, str) and driver else None,
        )

    @property
    def stored_flags(self) -> tuple[str, ...]:
        flags = self.stored["quality_flags"]
        return tuple(flags.split(FLAG_SEPARATOR)) if flags else ()

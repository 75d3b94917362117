"""Each exported episode's place in the four-layer record, so provenance survives export.

One :class:`Provenance` per episode: its session and trial, its participant, condition
and study step, outcome and interruption reason, quality flags, inclusion (and the reviewer
decision behind it), score and frame range, and who drove it. Every dataset format carries
the same fields (LeRobot: a sidecar table next to ``meta/``; HDF5: attributes of each demo).
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from dataclasses import asdict, dataclass
from typing import Any

from workcell.export.selection import EpisodeSource
from workcell.record.study_tags import StudyTags
from workcell.tasks.registry import recorded_task


@dataclass(frozen=True)
class Provenance:
    """Where one episode comes from and how it was judged (None: not recorded)."""

    episode_index: int
    session_id: str
    trial_id: str
    trial_index: int
    trial_seed: int | None
    operator_id: str
    """The participant (:mod:`workcell.record.study_tags`)."""
    condition: str | None
    """The session's study condition (None: none)."""
    study_step: int | None
    """Which of the participant's planned sessions it was (None: not a study's)."""
    mode: str
    round: int | None
    level: int | None
    required_boxes: int
    time_limit_s: float
    outcome: str
    interruption_reason: str | None
    elapsed_s: float | None
    completion_time_s: float | None
    boxes_delivered: int | None
    score: int | None
    n_frames: int
    quality_flags: tuple[str, ...]
    included: bool
    """The effective inclusion (see :mod:`workcell.export.selection`)."""
    exclusion_reason: str | None
    recorded_included: bool | None
    """The trial row's own ``included`` column."""
    review_kind: str | None
    review_by: str | None
    review_reason: str | None
    review_at_wall: float | None
    software_version: str
    task: str
    driver: str | None = None
    """Who drove the trial: ``person``, ``expert`` or ``policy:<id>`` (the trial's
    ``driver``; None: recorded before schema version 6). With an autonomous driver the
    episode is a rollout, corrected where its ``intervention`` frames say a person took
    over; a policy's rollout nobody took over is not a demonstration."""

    @classmethod
    def of(
        cls,
        episode_index: int,
        source: EpisodeSource,
        conditions: Mapping[str, Any] | None = None,
    ) -> Provenance:
        """``source``'s provenance; ``conditions``, the trial's recorded conditions, word
        its task text (:meth:`workcell.tasks.Task.trial_instruction`)."""
        trial, session, inclusion = source.trial, source.session, source.inclusion
        review = inclusion.review
        tags = StudyTags.of(session.operator_id, session.parameters)
        assert trial.outcome is not None and trial.n_frames is not None
        return cls(
            episode_index=episode_index,
            session_id=trial.session_id,
            trial_id=trial.trial_id,
            trial_index=trial.trial_index,
            trial_seed=trial.trial_seed,
            operator_id=tags.operator_id,
            condition=tags.condition,
            study_step=tags.study_step,
            mode=trial.mode,
            round=trial.round,
            level=trial.level,
            required_boxes=trial.required_boxes,
            time_limit_s=trial.time_limit_s,
            outcome=trial.outcome,
            interruption_reason=trial.interruption_reason,
            elapsed_s=trial.elapsed_s,
            completion_time_s=trial.completion_time_s,
            boxes_delivered=trial.boxes_delivered,
            score=trial.score,
            n_frames=trial.n_frames,
            quality_flags=trial.quality_flags,
            included=inclusion.included,
            exclusion_reason=inclusion.reason,
            recorded_included=trial.included,
            review_kind=review.kind if review else None,
            review_by=review.by if review else None,
            review_reason=review.reason if review else None,
            review_at_wall=review.at_wall if review else None,
            software_version=session.software_version,
            task=recorded_task(session.parameters).trial_instruction(
                trial.required_boxes, conditions or {}
            ),
            driver=trial.driver,
        )

    def as_dict(self) -> dict[str, Any]:
        values = asdict(self)
        values["quality_flags"] = list(self.quality_flags)
        return values

    def as_attributes(self) -> dict[str, Any]:
        """HDF5 attributes: fields that are None are left out (HDF5 has no null); the
        quality flags as JSON text."""
        attributes: dict[str, Any] = {}
        for name, value in self.as_dict().items():
            if value is None:
                continue  # absent attribute = not recorded
            attributes[name] = json.dumps(value) if isinstance(value, list) else value
        return attributes


PROVENANCE_FIELDS: tuple[str, ...] = tuple(Provenance.__dataclass_fields__)

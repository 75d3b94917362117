"""Each participant's sessions, in the order they run them.

Participant ``k`` of ``n`` is ``p01`` ... (``p`` and ``k`` zero-padded to at least two
digits): that is the operator id on all their sessions. For each condition in their order
(:mod:`workcell.study.order`) they run every step; a step's session seed is
``study.seed + 1000 k + step``, the same in every condition, so that a participant meets
the same worlds in each condition and the conditions are compared on equal terms.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

from workcell.session.config import SessionConfig
from workcell.study.config import StudyConfig, condition_session
from workcell.study.order import condition_order

SEEDS_PER_PARTICIPANT = 1000


@dataclass(frozen=True)
class PlannedSession:
    """One session of the plan: who, in which condition, which step, and its settings."""

    participant: str
    position: int
    """Its place in the participant's sequence, from 1."""
    condition: str
    step: int
    """Which of the study's steps, from 1."""
    config: SessionConfig


def participant_ids(study: StudyConfig) -> list[str]:
    width = max(2, len(str(study.participants)))
    return [f"p{k:0{width}d}" for k in range(1, study.participants + 1)]


def participant_number(study: StudyConfig, participant: str) -> int:
    """The number (from 1) of a participant id of the study; ValueError for another id."""
    ids = participant_ids(study)
    if participant not in ids:
        raise ValueError(f"participant {participant!r}: the study's are {ids[0]} to {ids[-1]}")
    return ids.index(participant) + 1


def participant_plan(study: StudyConfig, participant: str) -> list[PlannedSession]:
    """The sessions ``participant`` runs, in order."""
    number = participant_number(study, participant)
    order = condition_order(study.order, len(study.conditions), number, study.seed)
    sessions: list[PlannedSession] = []
    for index in order:
        condition = study.conditions[index]
        base = condition_session(study, condition)
        for step_number, step in enumerate(study.steps, start=1):
            task = dataclasses.replace(
                base.task, mode=step.mode, trials=step.trials if step.mode == "collection" else 0
            )
            config = dataclasses.replace(
                base,
                task=task,
                operator_id=participant,
                condition=condition.name,
                study_step=len(sessions) + 1,
                seed=study.seed + SEEDS_PER_PARTICIPANT * number + step_number,
            )
            sessions.append(
                PlannedSession(participant, len(sessions) + 1, condition.name, step_number, config)
            )
    return sessions

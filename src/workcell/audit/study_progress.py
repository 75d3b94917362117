"""What the audited sessions say of a study's plan (``workcell audit --study FILE``): the
study's name and design, and how many of each participant's planned sessions are done.

A planned session is done when the audited sessions hold a completed session of that
participant in that condition with that session seed, as ``workcell study`` and the study
server count it (:mod:`workcell.study.progress`). Sessions of an operator the study does
not hold (not one of its participant ids) are named apart.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from workcell.audit.rows import SessionRow
from workcell.study.config import StudyConfig
from workcell.study.plan import participant_ids, participant_plan
from workcell.study.progress import done_by


@dataclass(frozen=True)
class ParticipantProgress:
    participant: str
    planned: int
    """Sessions in their plan."""
    done: int
    """Of those, completed in the audited sessions."""
    order: tuple[str, ...]
    """The conditions in the order their plan runs them."""


@dataclass(frozen=True)
class StudyProgress:
    name: str
    order: str
    """How the study orders conditions (``latin_square``, ``fixed``, ``shuffled``)."""
    conditions: tuple[str, ...]
    participants: tuple[ParticipantProgress, ...]
    others: tuple[str, ...]
    """Operators of audited sessions that are not participants of the study."""

    @property
    def done(self) -> int:
        return sum(p.done for p in self.participants)

    @property
    def planned(self) -> int:
        return sum(p.planned for p in self.participants)

    def text(self) -> str:
        """``study pilot: 4 participants, 7 of 8 planned sessions done (p01 2/2, ...)``."""
        each = ", ".join(f"{p.participant} {p.done}/{p.planned}" for p in self.participants)
        return (
            f"study {self.name}: {len(self.participants)} participants, {self.done} of "
            f"{self.planned} planned sessions done ({each})"
        )


def study_progress(study: StudyConfig, sessions: Sequence[SessionRow]) -> StudyProgress:
    ids = participant_ids(study)
    participants = []
    for participant in ids:
        plan = participant_plan(study, participant)
        done = sum(
            any(done_by(planned, s.operator_id, s.condition, s.seed, s.status) for s in sessions)
            for planned in plan
        )
        order = tuple(dict.fromkeys(p.condition for p in plan))
        participants.append(ParticipantProgress(participant, len(plan), done, order))
    others = tuple(dict.fromkeys(s.operator_id for s in sessions if s.operator_id not in ids))
    return StudyProgress(
        name=study.name,
        order=study.order,
        conditions=tuple(c.name for c in study.conditions),
        participants=tuple(participants),
        others=others,
    )

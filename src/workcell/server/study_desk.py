"""The study a server runs (``workcell serve --study FILE``): who holds which invite, what
each participant runs next, and whether they have accepted the consent text.

A participant's session settings come from their plan (:mod:`workcell.study.plan`), never
from their browser; progress is read from the store (:mod:`workcell.study.progress`), so a
participant resumes where they left off after a dropped link or a server restart.
"""

from __future__ import annotations

import dataclasses
import hashlib
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from workcell.protocol.api import ParticipantStatus, PlannedStep
from workcell.protocol.messages import ErrorCode
from workcell.record.entries import SessionRecord, TrialRecord
from workcell.server.auth import ADMIN, Principal
from workcell.session.config import SessionConfig
from workcell.study.config import StudyConfig
from workcell.study.invites import Invites
from workcell.study.plan import PlannedSession, participant_ids, participant_plan
from workcell.study.progress import is_done, resume_point


@dataclass(frozen=True)
class Refusal:
    """Why a participant's session does not start, as the Error the client hears."""

    code: ErrorCode
    message: str


@dataclass(frozen=True)
class Recorded:
    """What the store holds: every session and trial (read once per question)."""

    sessions: Sequence[SessionRecord]
    trials: Sequence[TrialRecord]


class StudyDesk:
    def __init__(self, study: StudyConfig, invites: Invites, store: Path) -> None:
        self.study = study
        self.invites = invites
        self.store = store
        self.consent_digest = (
            hashlib.sha256(study.consent.encode()).hexdigest() if study.consent else ""
        )
        self.plans: dict[str, list[PlannedSession]] = {
            p: participant_plan(study, p) for p in participant_ids(study)
        }

    def tokens(self) -> dict[str, Principal]:
        """Every accepted token and its holder: the admin's, and the invite of each
        participant of the study (until it expires)."""
        days = self.study.invite_days
        held = {
            self.invites.participants[p]: Principal(p, self.invites.expires(p, days))
            for p in self.plans
        }
        return held | {self.invites.admin: ADMIN}

    def recorded(self) -> Recorded:
        """The store's sessions and trials (none before the store exists); blocking."""
        if not self.store.exists():
            return Recorded((), ())
        from workcell.record.store import Store  # noqa: PLC0415

        with Store.open(self.store, writer=False) as reader:
            return Recorded(reader.sessions(), reader.trials())

    def remaining(self, participant: str, recorded: Recorded) -> list[PlannedSession]:
        return [
            p for p in self.plans[participant] if not is_done(p, recorded.sessions, recorded.trials)
        ]

    def consented(self, participant: str, recorded: Recorded) -> bool:
        """No consent is asked, or a session of ``participant`` records its acceptance."""
        return not self.consent_digest or any(
            s.operator_id == participant and s.parameters.get("consent") == self.consent_digest
            for s in recorded.sessions
        )

    def status(self, participant: str) -> ParticipantStatus:
        recorded = self.recorded()
        remaining = self.remaining(participant, recorded)
        plan = self.plans[participant]
        return ParticipantStatus(
            study=self.study.name,
            participant=participant,
            instructions=self.study.instructions,
            consent=self.study.consent,
            consented=self.consented(participant, recorded),
            done=len(plan) - len(remaining),
            total=len(plan),
            next=planned_step(remaining[0], recorded) if remaining else None,
        )

    def next_session(self, participant: str, consent: bool) -> SessionConfig | Refusal:
        """The settings of ``participant``'s next session, or why it does not start."""
        recorded = self.recorded()
        remaining = self.remaining(participant, recorded)
        if not remaining:
            return Refusal(
                "not_allowed",
                f"start_session: you have run every session of study {self.study.name}; thank you",
            )
        if not (consent or self.consented(participant, recorded)):
            return Refusal(
                "not_allowed",
                "start_session: accept the study's consent text first (start_session.consent)",
            )
        planned = remaining[0]
        task = dataclasses.replace(
            planned.config.task,
            first_trial=resume_point(planned, recorded.sessions, recorded.trials),
        )
        return dataclasses.replace(planned.config, task=task, consent=self.consent_digest)


def planned_step(planned: PlannedSession, recorded: Recorded) -> PlannedStep:
    task = planned.config.task
    return PlannedStep(
        position=planned.position,
        condition=planned.condition,
        step=planned.step,
        mode=task.mode,
        trials={"practice": 1, "collection": task.trials}.get(task.mode, 0),
        trials_done=resume_point(planned, recorded.sessions, recorded.trials),
    )

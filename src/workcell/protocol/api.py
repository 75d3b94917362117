"""The JSON bodies of the server's read-only HTTP API (``/api/...``).

Like the WebSocket messages, these dataclasses are the single source of the TypeScript
types in ``web/src/protocol.ts``. Every response is one of them, encoded with
:func:`workcell.protocol.codec.encode`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

from workcell.protocol.messages import Scene
from workcell.protocol.scene import Pose

SettingKind = Literal["int", "float", "text", "choice", "int_list", "float_list", "bool"]


@dataclass(frozen=True)
class SettingInfo:
    """One setting of the setup page: its dotted ``key`` (as in the TOML file; the names
    of a :class:`~workcell.protocol.messages.FieldProblem` path), kind, default and documentation
    (which says the unit and the allowed range). ``choices`` lists a choice's values."""

    key: str
    kind: SettingKind
    default: object
    doc: str
    choices: tuple[str, ...] | None


@dataclass(frozen=True)
class SectionInfo:
    """A group of settings (``task``, ``world.robot``, ...) and its documentation."""

    key: str
    doc: str


@dataclass(frozen=True)
class Defaults:
    """``GET /api/defaults``: ``settings`` is the nested default mapping, ready to edit and
    send in :class:`~workcell.protocol.messages.StartSession`; ``fields`` describe every
    leaf setting in declaration order."""

    protocol: int
    settings: dict[str, object]
    sections: tuple[SectionInfo, ...]
    fields: tuple[SettingInfo, ...]


@dataclass(frozen=True)
class TrialSummary:
    """One recorded trial. ``outcome`` and the numbers after it are None while it runs."""

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
    boxes_delivered: int | None
    score: int | None
    n_frames: int | None
    quality_flags: tuple[str, ...]
    included: bool | None
    """Whether the trial is included, as :mod:`workcell.record.inclusion` decides (an
    interrupted trial never is; a reviewer's latest decision wins); None while it runs."""
    exclusion_reason: str | None
    """Why it is not included (``incomplete: interrupted (operator_stop)``, ...)."""
    started_wall: float


@dataclass(frozen=True)
class SessionSummary:
    """One recorded session and its trials (``status``: ``open`` or ``closed``), with its
    study tags (:mod:`workcell.record.study_tags`): ``operator_id`` (the participant),
    ``condition`` and ``study_step`` (None: none)."""

    session_id: str
    mode: str
    operator_id: str
    condition: str | None
    study_step: int | None
    created_wall: float
    ended_wall: float | None
    status: str
    trials: tuple[TrialSummary, ...]


@dataclass(frozen=True)
class SessionList:
    """``GET /api/sessions``: every session of the store, oldest first."""

    sessions: tuple[SessionSummary, ...]


@dataclass(frozen=True)
class ReplayFacts:
    """What the replay page says of its trial: who ran it (``operator_id``, the
    participant), in which ``condition`` and ``study_step`` (None: none), its mode and
    level, and how it ended (``outcome`` and the numbers after it: None while it runs)."""

    operator_id: str
    condition: str | None
    study_step: int | None
    mode: str
    round: int | None
    level: int | None
    required_boxes: int
    time_limit_s: float
    outcome: str | None
    interruption_reason: str | None
    elapsed_s: float | None
    boxes_delivered: int | None
    score: int | None
    included: bool | None
    exclusion_reason: str | None


@dataclass(frozen=True)
class TimelineEvent:
    """One recorded event of the trial at trial time ``t`` (s): its ``kind`` (a task event's,
    ``operator_action``, ...) and a short ``detail`` from its payload."""

    t: float
    kind: str
    detail: str


@dataclass(frozen=True)
class TrialReplay:
    """``GET /api/trials/{id}/frames?every=N``: every N-th recorded frame as the poses of
    the ``scene``'s dynamic bodies (in their index order, world frame), rebuilt from the
    recorded base pose, joints and boxes. ``t_sim[i]`` is the trial time of ``poses[i]``,
    which is recorded frame ``i * every`` of ``recorded_frames`` (the count the Sessions
    page shows)."""

    trial_id: str
    session_id: str
    every: int
    scene: Scene
    t_sim: tuple[float, ...]
    poses: tuple[tuple[Pose, ...], ...]
    recorded_frames: int
    facts: ReplayFacts
    events: tuple[TimelineEvent, ...]
    """The trial's events in time order, without the page's own telemetry
    (``client_frames``) and the media bookkeeping."""


@dataclass(frozen=True)
class ClientDiagnostics:
    """One connected client's counters; ``errors`` counts refused messages by code."""

    client: int
    role: str | None
    received: int
    errors: dict[str, int]
    states_sent: int
    states_dropped: int
    seat: str | None = None
    """The seat the client drives or watches (None before its hello)."""


@dataclass(frozen=True)
class SimDiagnostics:
    """The running session's real-time loop: steps late by more than one control period,
    wall time dropped after a stall, the longest step, and the real-time factor (sim
    seconds per wall second, the operator's pauses left out; 1 keeps real time): over the
    latest few seconds once measured, else since the session started. ``cores``: the CPU
    the session's process used over those seconds (0 until measured), ``paused_s`` the wall
    time it stood paused."""

    session_id: str
    control_period_s: float
    steps: int
    late_steps: int
    dropped_s: float
    max_step_ms: float
    real_time_factor: float
    seat: str = "1"
    cores: float = 0.0
    paused_s: float = 0.0


@dataclass(frozen=True)
class Diagnostics:
    """``GET /api/diagnostics``: the server process's CPU time, clients and simulations
    (``sim``: the first seat's running session; ``sims``: every running session)."""

    process_cpu_s: float
    clients: tuple[ClientDiagnostics, ...]
    sim: SimDiagnostics | None
    sims: tuple[SimDiagnostics, ...] = ()


@dataclass(frozen=True)
class PlannedStep:
    """One session of a study participant's plan: its place in their sequence (from 1),
    its condition, which of the study's steps (from 1), its mode and trials (0 for a
    challenge, which runs ``task.rounds`` rounds), and how many of its trials earlier
    sessions already ended (a step stopped part way resumes after them)."""

    position: int
    condition: str
    step: int
    mode: str
    trials: int
    trials_done: int = 0


@dataclass(frozen=True)
class ParticipantStatus:
    """``GET /api/study/me`` (a participant's invite): the study's texts, whether they
    have accepted its consent text, how far they are and what they run next (None: done)."""

    study: str
    participant: str
    instructions: str
    consent: str
    consented: bool
    done: int
    total: int
    next: PlannedStep | None


ParticipantState = Literal["offline", "waiting", "running", "finished"]


@dataclass(frozen=True)
class ParticipantRow:
    """One participant on the admin page: their invite link's path, progress, the condition
    they are in (running) or run next, their link and session (``rtt_ms``: the browser's
    last round trip; ``real_time_factor`` of the running session) and their recorded
    outcomes (trials ended, successes)."""

    participant: str
    invite: str
    state: ParticipantState
    done: int
    total: int
    condition: str | None
    session_id: str | None
    rtt_ms: float | None
    real_time_factor: float | None
    trials: int
    successes: int


@dataclass(frozen=True)
class StudyOverview:
    """``GET /api/study`` (the admin token): every participant, and how many sessions run
    of the most the server runs at once."""

    study: str
    running: int
    max_sessions: int
    participants: tuple[ParticipantRow, ...]
    behind: str = ""
    """In words, when running sessions fall behind real time (their trials are flagged
    ``sampling_gap``); empty when none does (:func:`workcell.server.admission.
    behind_real_time`)."""
    waiting: int = 0
    """Session starts waiting in line for headroom (:mod:`workcell.server.admission`)."""


API_TYPES: tuple[type, ...] = (
    SettingInfo,
    SectionInfo,
    Defaults,
    TrialSummary,
    SessionSummary,
    SessionList,
    TrialReplay,
    ClientDiagnostics,
    SimDiagnostics,
    Diagnostics,
    PlannedStep,
    ParticipantStatus,
    ParticipantRow,
    StudyOverview,
)

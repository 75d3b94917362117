"""Every message between the server and a browser client, versioned.

These dataclasses are the single source of truth: the TypeScript types in
``web/src/protocol.ts`` are generated from them (``python -m workcell.protocol.typescript``)
and a test fails when that file is stale. The task's events (:mod:`workcell.task.events`,
each a message of type ``event`` told apart by ``kind``) and its HUD
(:mod:`workcell.task.hud`) are sent as they are, so they are declared there, once. The
scene's parts are described in :mod:`workcell.protocol.scene`.
Direction is part of the type: a client can only send a :data:`ClientMessage` and the
server only sends a :data:`ServerMessage`. Every message is a JSON object with a ``type``
field naming it.

Coordinates: poses from the browser are in the WebXR ``local-floor`` reference space
(metres; x right, y up, -z forward) as (x, y, z, qw, qx, qy, qz); poses sent by the server
are in the MuJoCo world frame (z up), as (x, y, z, qw, qx, qy, qz).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

from workcell.protocol.scene import BodyDescription, MaterialDescription, Pose
from workcell.session.config import Mode
from workcell.task.events import (
    TASK_EVENTS,
    ActionSource,
    FrameFigures,
    OperatorAction,
    SessionEndReason,
    TaskEvent,
)
from workcell.task.hud import Hud

PROTOCOL_VERSION = 1
SUBPROTOCOL = f"workcell.v{PROTOCOL_VERSION}"
"""The WebSocket subprotocol a client must offer; another version is refused."""

Role = Literal["operator", "spectator"]
InputSource = Literal["xr", "xr_hands", "desktop", "gamepad"]
"""Where an input came from: WebXR controllers, WebXR with at least one tracked hand (a hand
reads as a controller: wrist pose, pinch as trigger, grab as grip), keyboard and mouse, or a
gamepad."""
ErrorCode = Literal[
    "malformed",
    "too_large",
    "invalid_value",
    "not_allowed",
    "rate_limited",
    "protocol",
    "server_full",
]


# --- client -> server -------------------------------------------------------------------------


@dataclass(frozen=True)
class Hello:
    """First message of a connection: who the client wants to be. ``resume_token`` (from
    a previous :class:`Welcome`) takes back control of a session after a dropped link.
    ``seat`` names the session a spectator watches (a :class:`Welcome`'s ``seat``; none:
    the first); an operator gets a seat of its own while the server has room."""

    role: Role
    resume_token: str | None = None
    seat: str | None = None
    type: Literal["hello"] = "hello"


@dataclass(frozen=True)
class StartSession:
    """Start a session with these settings: the nested TOML structure of
    ``workcell config --defaults`` as JSON (missing keys keep their defaults)."""

    settings: dict[str, object]
    consent: bool = False
    """The operator accepted the study's consent text (``workcell serve --study``: the
    first session of a study with consent text needs it; the settings come from the
    participant's plan and ``settings`` is ignored)."""
    type: Literal["start_session"] = "start_session"


@dataclass(frozen=True)
class ControllerState:
    """One hand's raw device state. ``pose`` is None while the device is not tracked;
    ``grip``, ``trigger`` in [0, 1]; ``stick`` (x right, y forward) in [-1, 1];
    ``buttons`` a bit mask (bit 0: A/X, bit 1: B/Y, bit 2: stick press, bit 3: menu)."""

    pose: Pose | None
    grip: float
    trigger: float
    stick: tuple[float, float]
    buttons: int


@dataclass(frozen=True)
class Input:
    """Raw device state, sent every animation frame. ``seq`` increases by one per input;
    older sequence numbers than the last seen are dropped. ``t_client`` is the client's
    clock in seconds (for latency diagnostics only)."""

    seq: int
    t_client: float
    source: InputSource
    headset: Pose | None
    left: ControllerState
    right: ControllerState
    type: Literal["input"] = "input"


@dataclass(frozen=True)
class Stop:
    """The operator ends the session (the running trial ends interrupted: operator_stop);
    ``reason``, their words (up to :data:`~workcell.task.events.STOP_NOTE_MAX`
    characters, may be empty), is recorded in a ``stop_requested`` event."""

    reason: str = ""
    type: Literal["stop"] = "stop"


@dataclass(frozen=True)
class Pause:
    """The operator pauses (``paused``) or resumes the running trial: while paused the
    physics and the trial's clock stand still; recorded as ``paused`` and ``resumed``
    events. A pause asked during a countdown begins when the trial's clock starts."""

    paused: bool
    type: Literal["pause"] = "pause"


@dataclass(frozen=True)
class Act:
    """The operator used a control of the application besides driving (the in-VR menu or
    its desktop counterpart); recorded as an ``operator_action`` event of the trial under
    way. ``restart_trial`` also ends the running trial (interrupted: operator_restart) and
    begins a new one of the same kind."""

    action: OperatorAction
    source: ActionSource
    type: Literal["act"] = "act"


@dataclass(frozen=True)
class TakeOver:
    """The person takes control from the session's autonomous driver (``driver`` expert
    or a policy) at once, without a jump: each arm's current target becomes its clutch's
    anchor. Recorded as a ``take_over`` event with ``reason`` (their words, up to
    :data:`~workcell.task.events.STOP_NOTE_MAX` characters, may be empty); refused in a
    session the person drives anyway."""

    reason: str = ""
    type: Literal["take_over"] = "take_over"


@dataclass(frozen=True)
class HandBack:
    """The person gives control back to the session's driver, which goes on from the
    state it finds (the expert re-plans, a policy drops its queued actions). Recorded as a
    ``hand_back`` event with ``reason``."""

    reason: str = ""
    type: Literal["hand_back"] = "hand_back"


@dataclass(frozen=True, kw_only=True)
class FrameStats(FrameFigures):
    """How the operator's browser draws, over the frames since its previous report (every
    few seconds; the fields are :class:`~workcell.task.events.FrameFigures`'). Recorded as
    a ``client_frames`` event of the trial under way."""

    type: Literal["frame_stats"] = "frame_stats"


@dataclass(frozen=True)
class Ping:
    """Asks for a :class:`Pong` (round-trip time); ``t_client`` comes back unchanged."""

    t_client: float
    rtt_ms: float | None = None
    """The client's previous round-trip time, for the server's diagnostics and the study's
    admin page (None before the first pong)."""
    type: Literal["ping"] = "ping"


ClientMessage = (
    Hello | StartSession | Input | Stop | Pause | Act | TakeOver | HandBack | FrameStats | Ping
)


# --- server -> client -------------------------------------------------------------------------


@dataclass(frozen=True)
class Welcome:
    """Answer to :class:`Hello`: the granted role (an operator the server has no seat for
    becomes a spectator, told so by a ``server_full`` :class:`Error`), the seat (whose
    session the client drives or watches), the running session if any, and the token that
    resumes control after a dropped link."""

    protocol: int
    role: Role
    session_id: str | None
    resume_token: str | None
    grace_s: float
    seat: str = "1"
    type: Literal["welcome"] = "welcome"


@dataclass(frozen=True)
class Scene:
    """Everything to draw, derived from the compiled MuJoCo model. Sent on connect and
    when a session starts."""

    bodies: tuple[BodyDescription, ...]
    head_camera_body: str
    materials: tuple[MaterialDescription, ...] = ()
    type: Literal["scene"] = "scene"


@dataclass(frozen=True)
class State:
    """The latest poses of the dynamic bodies (in :class:`~workcell.protocol.scene.BodyDescription`
    index order),
        sent at up to 60 Hz; a client that falls behind gets only the newest."""

    seq: int
    t_sim: float
    poses: tuple[Pose, ...]
    hud: Hud | None
    input_seq: int
    """The last input sequence number applied to the simulation (for latency)."""
    tcp_targets: tuple[Pose, Pose]
    """Where the left and right TCP are asked to be (world frame), to draw as ghosts."""
    following: tuple[bool, bool]
    """Whether the left and right arm follow their controller (grip held)."""
    type: Literal["state"] = "state"


@dataclass(frozen=True)
class FieldProblem:
    """One invalid value, as data: ``path`` names where it is (the dotted setting name
    split at its dots, list indices as numbers: ``["task", "level_boxes", 1]``; empty when
    the problem names no field), ``value`` is what was given (null when it has no JSON
    form) and ``allowed`` what would be accepted; ``message`` says it all in one line."""

    path: tuple[str | int, ...]
    value: object
    allowed: str
    message: str


@dataclass(frozen=True)
class ConfigRejected:
    """A :class:`StartSession` whose settings were invalid; nothing was started."""

    problems: tuple[FieldProblem, ...]
    type: Literal["config_rejected"] = "config_rejected"


@dataclass(frozen=True)
class SessionStarted:
    """A session began (sent to every client): its id and the settings it runs under."""

    session_id: str
    mode: Mode
    operator_id: str
    settings: dict[str, object]
    type: Literal["session_started"] = "session_started"


@dataclass(frozen=True)
class SessionEnded:
    """The session is over (completed, stopped, or its operator was lost)."""

    session_id: str
    reason: SessionEndReason
    trials: int
    successes: int
    total_score: int
    detail: str = ""
    """What went wrong, when ``reason`` is ``"error"`` or ``"storage_error"`` (e.g. the
    disk is full, the store writer process died)."""
    stop_note: str = ""
    """Why whoever stopped the session did (their words), when it was stopped with one."""
    type: Literal["session_ended"] = "session_ended"


@dataclass(frozen=True)
class Error:
    """A message was refused. ``code``: ``malformed``, ``too_large``, ``invalid_value``,
    ``not_allowed``, ``rate_limited``, ``protocol``, ``server_full`` (an operator's hello
    when every seat has an operator). The connection stays open unless ``fatal``."""

    code: ErrorCode
    message: str
    fatal: bool = False
    problem: FieldProblem | None = None
    """The refused value as data, when the problem is one field's."""
    type: Literal["error"] = "error"


@dataclass(frozen=True)
class Queued:
    """The operator's :class:`StartSession` waits: the machine has no headroom for one
    more session at real time (:mod:`workcell.server.admission`). ``position`` (from 1)
    in the line of ``waiting`` starts; the server starts it by itself once there is room
    and sends this again whenever the position or the reason changes."""

    position: int
    waiting: int
    message: str
    type: Literal["queued"] = "queued"


@dataclass(frozen=True)
class Pong:
    """Answer to :class:`Ping`: its ``t_client`` and the server's clock (Unix seconds)."""

    t_client: float
    t_server: float
    type: Literal["pong"] = "pong"


ServerMessage = (
    Welcome
    | Scene
    | State
    | TaskEvent
    | ConfigRejected
    | SessionStarted
    | SessionEnded
    | Error
    | Queued
    | Pong
)

CLIENT_MESSAGES: tuple[type, ...] = (
    Hello,
    StartSession,
    Input,
    Stop,
    Pause,
    Act,
    TakeOver,
    HandBack,
    FrameStats,
    Ping,
)
SERVER_MESSAGES: tuple[type, ...] = (
    Welcome,
    Scene,
    State,
    *TASK_EVENTS,
    ConfigRejected,
    SessionStarted,
    SessionEnded,
    Error,
    Queued,
    Pong,
)

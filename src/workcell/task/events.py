"""Typed task events: every transition of a session, published to subscribers.

Each event is also the message the server sends for it (``type`` ``"event"``, told apart
by ``kind``): the TypeScript union ``TaskEvent`` in ``web/src/protocol.ts`` is generated
from these classes. ``t_sim`` is trial time (0 when the trial's clock starts; negative
during the countdown). The box events are the world's (:mod:`workcell.sim.events`)
stamped with the trial.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Literal, get_args

from workcell.session.config import Mode
from workcell.sim import events as world

Outcome = Literal["success", "timeout", "interrupted", "failed"]
"""How a trial ended: its task done (``success``), its time up (``timeout``), stopped before
either (``interrupted``, with a reason), or its task's judge saying it can no longer
succeed (``failed``, added with the task API; box transfer's judge never says so)."""
InterruptionReason = Literal[
    "operator_stop",
    "application_quit",
    "client_lost",
    "crash_recovered",
    "storage_error",
    "operator_restart",
    "admin_stop",
]
SessionEndReason = Literal["completed", "error", InterruptionReason]
"""Why a session ended: its campaign completed, it was interrupted (the reason its last
trial was interrupted with), or an ``error`` stopped it."""

_WIRE_ONLY = ("t_sim", "kind", "type")
"""Fields that are not part of an event's stored payload (the store has columns for
``t_sim`` and ``kind``; ``type`` names the message)."""


@dataclass(frozen=True)
class CountdownStarted:
    """A trial's countdown began (``seconds`` long)."""

    trial_index: int
    t_sim: float
    seconds: float
    kind: Literal["countdown_started"] = "countdown_started"
    type: Literal["event"] = "event"


@dataclass(frozen=True)
class TrialStarted:
    """A trial's clock started."""

    trial_index: int
    t_sim: float
    mode: Mode
    round: int | None
    level: int | None
    required_boxes: int
    time_limit_s: float
    trial_seed: int
    conditions: dict[str, object]
    """The trial's box, belt, feed, target and start conditions (randomized or not)."""
    kind: Literal["trial_started"] = "trial_started"
    type: Literal["event"] = "event"


@dataclass(frozen=True)
class BoxReleased(world.BoxReleased):
    """The feeder put a box on the belt start."""

    trial_index: int
    kind: Literal["box_released"] = "box_released"
    type: Literal["event"] = "event"


@dataclass(frozen=True)
class GraspChanged(world.GraspChanged):
    """Both pads closed on a box (``engaged``) or let go of it."""

    trial_index: int
    kind: Literal["grasp_changed"] = "grasp_changed"
    type: Literal["event"] = "event"


@dataclass(frozen=True)
class BoxDelivered(world.BoxCompleted):
    """A released box came to rest where the trial's task wants it while the trial ran (box
    transfer's zone, a pallet slot, its kind's table: the scene's ``BoxCompleted``), under
    the record's event kind ``box_delivered``; ``boxes_delivered`` counts the trial's boxes
    done so far."""

    trial_index: int
    boxes_delivered: int
    kind: Literal["box_delivered"] = "box_delivered"
    type: Literal["event"] = "event"


@dataclass(frozen=True)
class LevelChanged:
    """The campaign moves to another level (after a success) or repeats it (timeout)."""

    trial_index: int
    t_sim: float
    round: int
    level: int
    repeat: bool
    kind: Literal["level_changed"] = "level_changed"
    type: Literal["event"] = "event"


@dataclass(frozen=True)
class TrialTimedOut:
    """The trial's time limit passed."""

    trial_index: int
    t_sim: float
    kind: Literal["trial_timed_out"] = "trial_timed_out"
    type: Literal["event"] = "event"


@dataclass(frozen=True)
class TrialInterrupted:
    """The trial was cut short (``reason``)."""

    trial_index: int
    t_sim: float
    reason: InterruptionReason
    kind: Literal["trial_interrupted"] = "trial_interrupted"
    type: Literal["event"] = "event"


StopBy = Literal["operator", "admin"]
"""Who asked a session to stop: its operator, or the study's admin."""
STOP_NOTE_MAX = 300
"""Longest stop reason (characters) an operator or the admin may give."""


@dataclass(frozen=True)
class StopRequested:
    """Someone asked the session to stop (``by``), for ``reason`` (their words, possibly
    empty); recorded in the trial under way just before it ends interrupted."""

    trial_index: int
    t_sim: float
    by: StopBy
    reason: str
    kind: Literal["stop_requested"] = "stop_requested"
    type: Literal["event"] = "event"


@dataclass(frozen=True)
class Paused:
    """The operator paused the trial: its clock and the physics stop until
    :class:`Resumed` (``t_sim`` is the same at both)."""

    trial_index: int
    t_sim: float
    kind: Literal["paused"] = "paused"
    type: Literal["event"] = "event"


@dataclass(frozen=True)
class Resumed:
    """The paused trial runs again after ``paused_s`` seconds of wall time, which its
    clock, its elapsed and completion times and the audit's wall-clock sampling check do
    not count."""

    trial_index: int
    t_sim: float
    paused_s: float
    kind: Literal["resumed"] = "resumed"
    type: Literal["event"] = "event"


OperatorAction = Literal[
    "restart_trial",
    "recenter_view",
    "view_first",
    "view_third",
    "turn_snap",
    "turn_smooth",
    "snap_left",
    "snap_right",
]
"""What an operator can do from the in-VR menu (or its desktop counterpart) besides driving:
start the trial over (the attempt ends interrupted, ``operator_restart``, and a new trial
of the same kind begins), recenter the headset view, switch to first or third person,
switch the right stick to snap turns or back to smooth turning; with snap turns, a flick
of the stick asks for one (``snap_left``/``snap_right``: the base turns 30 degrees while
the client blacks the view out)."""
ActionSource = Literal["xr_menu", "xr_button", "desktop"]
"""Where an action came from: the in-VR menu, a controller button (B/Y switches the view),
or the desktop page (toolbar, keys)."""


@dataclass(frozen=True)
class OperatorActed:
    """The operator used a control of the application (``action``, from ``source``)."""

    trial_index: int
    t_sim: float
    action: OperatorAction
    source: ActionSource
    kind: Literal["operator_action"] = "operator_action"
    type: Literal["event"] = "event"


@dataclass(frozen=True)
class FrameFigures:
    """How the operator's browser drew over its last few seconds: frame intervals in ms
    (p50, p95, the longest), the WebGL draw calls and triangles of a frame (both eyes in a
    headset), and whether it presented to a headset. The client sends them (the
    protocol's ``FrameStats``); the record keeps them (:class:`ClientFrames`)."""

    frames: int
    frame_ms_p50: float
    frame_ms_p95: float
    frame_ms_max: float
    draw_calls: int
    triangles: int
    presenting: bool


@dataclass(frozen=True, kw_only=True)
class ClientFrames(FrameFigures):
    """A :class:`FrameFigures` report, in the trial under way."""

    trial_index: int
    t_sim: float
    kind: Literal["client_frames"] = "client_frames"
    type: Literal["event"] = "event"


@dataclass(frozen=True)
class TookOver:
    """The person (``operator_id``) took control from the session's autonomous
    ``driver`` (``expert`` or ``policy:<id>``), for ``reason`` (their words, possibly
    empty): the frames after it are corrections (``intervention`` 1) until
    :class:`HandedBack`."""

    trial_index: int
    t_sim: float
    operator_id: str
    driver: str
    reason: str
    kind: Literal["take_over"] = "take_over"
    type: Literal["event"] = "event"


@dataclass(frozen=True)
class HandedBack:
    """The person (``operator_id``) gave control back to ``driver``, which goes on from
    the state it finds; ``reason`` their words, possibly empty."""

    trial_index: int
    t_sim: float
    operator_id: str
    driver: str
    reason: str
    kind: Literal["hand_back"] = "hand_back"
    type: Literal["event"] = "event"


@dataclass(frozen=True)
class TrialEnded:
    """A trial is over: its outcome, time, deliveries and score."""

    trial_index: int
    t_sim: float
    outcome: Outcome
    interruption_reason: InterruptionReason | None
    elapsed_s: float
    boxes_delivered: int
    score: int
    kind: Literal["trial_ended"] = "trial_ended"
    type: Literal["event"] = "event"


TaskEvent = (
    CountdownStarted
    | TrialStarted
    | BoxReleased
    | GraspChanged
    | BoxDelivered
    | LevelChanged
    | TrialTimedOut
    | TrialInterrupted
    | TrialEnded
    | OperatorActed
    | ClientFrames
    | StopRequested
    | Paused
    | Resumed
    | TookOver
    | HandedBack
)
TASK_EVENTS: tuple[type[TaskEvent], ...] = get_args(TaskEvent)


def event_kind(event: TaskEvent) -> str:
    """The stored name of an event type: ``trial_started``, ``box_delivered``, ..."""
    return event.kind


def event_payload(event: TaskEvent) -> dict[str, object]:
    """What the store keeps of an event beside its kind and time: the trial index first,
    then the event's own fields in declaration order."""
    payload: dict[str, object] = {"trial_index": event.trial_index}
    for field in dataclasses.fields(event):
        if field.name not in _WIRE_ONLY:
            payload[field.name] = getattr(event, field.name)
    return payload


def stamped(
    event: world.WorldEvent, trial_index: int, t_sim: float, boxes_delivered: int
) -> TaskEvent:
    """A world event as the task publishes it: on the trial clock, with its trial
    (``boxes_delivered`` is the trial's count including a delivery ``event`` makes)."""
    if isinstance(event, world.BoxReleased):
        return BoxReleased(t_sim=t_sim, box=event.box, trial_index=trial_index)
    if isinstance(event, world.GraspChanged):
        return GraspChanged(t_sim, event.box, event.engaged, trial_index=trial_index)
    return BoxDelivered(t_sim, event.box, trial_index, boxes_delivered)

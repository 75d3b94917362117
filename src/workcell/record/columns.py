"""Column names of the four layers: the interchange contract of docs/architecture.md, defined once.

The contract's columns come first, in the contract's order; further columns follow. These
names are public API: CSV headers, SQL columns and dataset features use them verbatim.
"""

from __future__ import annotations

from typing import get_args

from workcell.metrics.definitions import STORED_METRICS
from workcell.sim.joints import JOINT_ORDER
from workcell.task.events import InterruptionReason, Outcome

POSE_SUFFIXES: tuple[str, ...] = ("x", "y", "z", "qw", "qx", "qy", "qz")


def pose_columns(prefix: str) -> tuple[str, ...]:
    """``<prefix>_x .. <prefix>_qz``: a position and a (w, x, y, z) quaternion."""
    return tuple(f"{prefix}_{s}" for s in POSE_SUFFIXES)


BASE_COLUMNS: tuple[str, ...] = ("base_x", "base_y", "base_yaw", "base_vx", "base_vy", "base_wz")
"""The base's pose (x, y, yaw) and velocity (vx, vy, wz) in the world frame."""
GRIPPER_COLUMNS: tuple[str, ...] = ("gripper_l", "gripper_r")
"""The measured finger openings, 0 closed .. 1 open."""
HAND_COLUMNS: tuple[str, ...] = ("grip_l", "grip_r", "trigger_l", "trigger_r", *GRIPPER_COLUMNS)
"""Per hand: the operator's grip and trigger (0-1) and the gripper's measured opening."""

FRAME_CONTRACT_COLUMNS: tuple[str, ...] = (
    "session_id",
    "trial_id",
    "frame_index",
    "t_sim",
    "t_wall",
    *BASE_COLUMNS,
    *pose_columns("tcp_l"),
    *pose_columns("tcp_r"),
    *(f"q_{j}" for j in JOINT_ORDER),
    *(f"dq_{j}" for j in JOINT_ORDER),
    *HAND_COLUMNS,
)
"""frames.csv's contract columns. Units SI, radians, world frame z-up; ``t_sim`` is 0 at the
trial start, ``t_wall`` Unix seconds; grip and trigger are the operator's input values
(0-1), gripper the measured opening (0 closed .. 1 open). The base velocity is in the world
frame."""

COMMAND_COLUMNS: tuple[str, ...] = (
    "cmd_vx",
    "cmd_vy",
    "cmd_wz",
    *pose_columns("target_l"),
    *pose_columns("target_r"),
    "follow_l",
    "follow_r",
    "gripper_cmd_l",
    "gripper_cmd_r",
    "head_cmd_pan",
    "head_cmd_tilt",
)
"""The command the operator gave (the action): base twist, both TCP targets (base frame),
follow flags, gripper closes, head pan and tilt."""

_DEVICE_STATE_COLUMNS: tuple[str, ...] = (
    *pose_columns("ctrl_l"),
    *pose_columns("ctrl_r"),
    *pose_columns("headset"),
    "stick_l_x",
    "stick_l_y",
    "stick_r_x",
    "stick_r_y",
    "buttons_l",
    "buttons_r",
)

FRAME_EXTRA_COLUMNS: tuple[str, ...] = (
    *COMMAND_COLUMNS,
    # raw device state; NULL (empty in CSV) for operators without that device
    *_DEVICE_STATE_COLUMNS,
    # grasp signals: box index, or -1 for none
    "contact_l",
    "contact_r",
    "attached",
    # every box: JSON list of [index, state, x, y, z, qw, qx, qy, qz]
    "boxes",
    # diagnostics
    "step_wall_ms",
    "ik_residual_l",
    "ik_residual_r",
    "input_age_s",
)
"""Further frame columns after the contract's. ``target_*`` are base-frame TCP targets;
``follow_*`` 0/1; ``buttons_*`` a bit mask; ``step_wall_ms`` the wall time of the control
step that produced the frame; ``input_age_s`` how old the operator input was."""

FILTERED_POSE_COLUMNS: tuple[str, ...] = (
    *pose_columns("ctrl_l_filtered"),
    *pose_columns("ctrl_r_filtered"),
    *pose_columns("headset_filtered"),
)
"""The device poses the teleoperation acted on: ``ctrl_l``, ``ctrl_r`` and ``headset`` after
the session's pose filter (``input.filter``, a One-Euro filter by default), in the same
tracking frame; equal to the raw poses when the filter is off, NULL where the raw pose is.
Added by schema version 3, after every earlier column (frames recorded before it hold NULL)."""

FRAME_TASK_COLUMNS: tuple[str, ...] = ("stage", "progress")
"""How the trial stood at the frame's instant, as the session runner saw it: its task's
judge's ``stage`` (the furthest of the task's stages reached) and ``progress`` (0..1; see
:class:`workcell.tasks.Evaluation`), the latest judgement at or before the instant. Added by
schema version 5, after every earlier column (frames recorded before it hold NULL)."""

FRAME_INTERVENTION_COLUMNS: tuple[str, ...] = ("intervention",)
"""Who drove at the frame's instant: ``intervention`` 1 while the person has taken control
from the session's autonomous driver (a correction), 0 while the driver drives (in a
session whose driver is the person there is nothing to take over: 0 throughout; see the
trial's ``driver``). LeRobot's per-frame feature of the same name. Added by schema version
6, after every earlier column (frames recorded before it hold NULL)."""

FRAME_COLUMNS: tuple[str, ...] = (
    FRAME_CONTRACT_COLUMNS
    + FRAME_EXTRA_COLUMNS
    + FILTERED_POSE_COLUMNS
    + FRAME_TASK_COLUMNS
    + FRAME_INTERVENTION_COLUMNS
)

TRIAL_COLUMNS: tuple[str, ...] = (
    "session_id",
    "trial_id",
    "trial_index",
    "mode",
    "round",
    "level",
    "required_boxes",
    "time_limit_s",
    "outcome",
    "interruption_reason",
    "elapsed_s",
    "completion_time_s",
    "boxes_delivered",
    "score",
    "n_frames",
    *(name for name in STORED_METRICS if name != "completion_time_s"),
    "quality_flags",
    "included",
    "exclusion_reason",
)
"""trials.csv's columns, in the contract's order: the trial's result, then the frame count
and the stored metrics of :mod:`workcell.metrics.definitions` (``completion_time_s``, a
result as much as a metric, stands beside ``elapsed_s``)."""

TRIAL_TASK_COLUMNS: tuple[str, ...] = ("task", "world", "stage", "progress", "goal_json")
"""A trial's task-neutral columns, the same for every task (added by schema version 5; NULL
in trials recorded before it): ``task`` the session's ``task.kind`` as recorded (a
built-in name or ``module:Class``), ``world`` the named world its ranges are (``D0``,
``D1``, ``D2``; NULL for ranges of no named world), ``stage`` the furthest of the task's
stages the trial reached and ``progress`` (0..1) its final progress, both as its task's
judge said at its last frame instant, and ``goal_json`` what the trial asked as numbers,
a JSON object of the task's ``goal_names`` (:meth:`workcell.tasks.Task.goal`)."""

TRIAL_DRIVER_COLUMNS: tuple[str, ...] = ("driver",)
"""Who drove the trial (added by schema version 6; NULL in trials recorded before it):
``person`` (a person at a browser or headset), ``expert`` (the task's scripted expert),
``policy:<id>`` (a learned policy, its checkpoint's operator id) or ``generated``
(``workcell generate``). With an autonomous driver a person may have taken over: the
frames' ``intervention`` column and the ``take_over``/``hand_back`` events say when."""

TRIALS_CSV_COLUMNS: tuple[str, ...] = TRIAL_COLUMNS + TRIAL_TASK_COLUMNS + TRIAL_DRIVER_COLUMNS
"""trials.csv's columns: the contract's, then (since schema version 5) the task-neutral ones
and (since version 6) the driver."""

OUTCOMES: tuple[str, ...] = get_args(Outcome)
"""Every trial outcome: ``success``, ``timeout``, ``interrupted`` and (since the task API)
``failed``, a trial its task's judge said could no longer succeed."""
COMPLETE_OUTCOMES: tuple[str, ...] = tuple(o for o in OUTCOMES if o != "interrupted")
"""The outcomes of a complete trial (it ran to an end its task or its clock decided):
everything but ``interrupted``."""
INTERRUPTION_REASONS: tuple[str, ...] = get_args(InterruptionReason)

FRAME_DEVICE_COLUMNS: tuple[str, ...] = (
    *_DEVICE_STATE_COLUMNS,
    "input_age_s",
    *FILTERED_POSE_COLUMNS,
)
"""Device state (raw and filtered) and its age: the only frame columns that may be NULL
(empty in CSV), for operators without that device (the scripted expert, replay)."""

SESSION_COLUMNS: tuple[str, ...] = (
    "session_id",
    "created_wall",
    "ended_wall",
    "schema_version",
    "software_version",
    "mode",
    "operator_id",
    "seed",
    "parameters_json",
    "thresholds_json",
    "joint_order_json",
    "metric_definitions_json",
    "metrics_version",
    "status",
)
"""sessions.csv's columns. ``*_json`` hold JSON text; ``status`` is one of
:data:`SESSION_STATUSES`; times are Unix seconds."""

EVENT_COLUMNS: tuple[str, ...] = (
    "event_id",
    "session_id",
    "trial_id",
    "seq",
    "t_sim",
    "t_wall",
    "kind",
    "payload_json",
)
"""events.csv's columns. ``trial_id`` is empty for session-level events; ``seq`` counts the
session's events from 0; ``t_sim`` is the trial's sim clock (empty for session events)."""

ANNOTATION_COLUMNS: tuple[str, ...] = (
    "annotation_id",
    "trial_id",
    "kind",
    "reason",
    "by",
    "at_wall",
)
"""annotations.csv's columns: a reviewer's decision on a trial (who, when, why)."""

SESSION_STATUSES: tuple[str, ...] = ("running", "completed", "interrupted", "recovered")
"""``running`` while recording; ``completed`` or ``interrupted`` when closed by the recorder;
``recovered`` when closed by crash recovery on the next open."""

ANNOTATION_KINDS: tuple[str, ...] = ("include", "exclude", "note")

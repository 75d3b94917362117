"""What one trial's Rerun recording holds, and where (entity paths are public API).

::

    /                          static AnyValues: the episode's Provenance fields (null where
                               not recorded; quality_flags one string per flag)
    /provenance                static TextDocument (markdown): the provenance document of
                               the export, narrowed to this episode and its session (JSON)
    /world                     static ViewCoordinates: right-handed, z up (metres)
    /world/base                Transform3D: base_x, base_y, 0 and base_yaw about z
                               (+ static axis length: the base's axes are drawn)
    /world/tcp_l, tcp_r        Points3D: the TCP world positions (tcp_*_x, _y, _z)
    /world/trajectories/base   static LineStrips3D: the base's path on the floor (z = 0)
    /world/trajectories/tcp_l  static LineStrips3D: the TCP paths, likewise tcp_r
    /world/boxes               Boxes3D: every box of the pool at every frame, coloured by
                               state (parked grey, active box colour, delivered green);
                               static: half sizes (the trial's box size), labels box<i>
    /joints/<joint>            Scalars: q_<joint>, one entity per joint of JOINT_ORDER
                               (radians; the spine in metres)
    /hands/<column>            Scalars: grip_l, grip_r, trigger_l, trigger_r (operator input
                               0-1), gripper_l, gripper_r (opening, 0 closed .. 1 open)
    /events                    TextLog: every task event of the trial at its t_sim

Timelines: ``frame`` (sequence, the store's ``frame_index``) and ``t_sim`` (duration,
seconds from the trial start). Events sit on ``t_sim`` at their own time (the countdown's
are negative), on ``frame`` at the last frame recorded at or before it (frame 0 before
the first) and on ``event`` (sequence: 0, 1, ... in the trial's event order; several
events can share a frame or a time, never an ``event`` value). Every per-frame entity has
exactly one row per recorded frame.

Written with rerun-sdk 0.26 (pinned; the version LeRobot 0.4 pins): open the files with the
Rerun viewer 0.26.
"""

from __future__ import annotations

import json
import typing
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import pyarrow as pa  # type: ignore[import-untyped, unused-ignore]
import rerun as rr
import rerun.blueprint as rrb
from numpy.typing import NDArray

from workcell.export.boxes import BOX_STATE_CODES, BoxTrack
from workcell.export.provenance import Provenance
from workcell.record.columns import HAND_COLUMNS
from workcell.record.entries import EventRecord
from workcell.sim.joints import JOINT_ORDER
from workcell.tasks.task import ObjectLook

APPLICATION_ID = "workcell"
FRAME_TIMELINE = "frame"
TIME_TIMELINE = "t_sim"
EVENT_TIMELINE = "event"

PROVENANCE_ENTITY = "provenance"
WORLD = "world"
BASE_ENTITY = "world/base"
BOXES_ENTITY = "world/boxes"
TRAJECTORIES = "world/trajectories"
EVENTS_ENTITY = "events"
JOINTS = "joints"
HANDS = "hands"
TCPS: tuple[str, ...] = ("tcp_l", "tcp_r")
WARNING_EVENTS = frozenset({"trial_timed_out", "trial_interrupted", "interruption", "recovery"})
"""Event kinds logged at level WARN (every other kind at INFO)."""

TCP_COLORS: dict[str, tuple[int, int, int, int]] = {
    "tcp_l": (66, 135, 245, 255),
    "tcp_r": (235, 64, 52, 255),
}
BASE_COLOR = (120, 120, 120, 255)
DELIVERED_COLOR = (60, 180, 75, 255)
PARKED_COLOR = (150, 150, 150, 255)
TCP_RADIUS = 0.03
PATH_RADIUS = 0.005
AXIS_LENGTH = 0.4


def joint_entity(joint: str) -> str:
    return f"{JOINTS}/{joint}"


def hand_entity(column: str) -> str:
    return f"{HANDS}/{column}"


def tcp_entity(tcp: str) -> str:
    """``tcp``: ``tcp_l`` or ``tcp_r``."""
    return f"{WORLD}/{tcp}"


def trajectory_entity(name: str) -> str:
    """``name``: ``base``, ``tcp_l`` or ``tcp_r``."""
    return f"{TRAJECTORIES}/{name}"


@dataclass(frozen=True)
class TrialRecording:
    """Everything one trial's recording is made of."""

    provenance: Provenance
    document: dict[str, Any]
    """The provenance document (see :mod:`workcell.export.manifest`) for this episode."""
    frames: Mapping[str, NDArray[Any]]
    """The trial's frame columns (``Store.frames``)."""
    boxes: BoxTrack
    box_looks: tuple[ObjectLook, ...]
    """Each pooled box's size and colour in the trial (its task's
    :meth:`~workcell.tasks.task.Task.object_looks`: sort's two kinds differ)."""
    events: Sequence[EventRecord]
    started_wall: float

    @property
    def length(self) -> int:
        return len(self.frames["frame_index"])


def blueprint() -> rrb.Blueprint:
    """The default layout: the workcell in 3D, joints and hands over time, the event log."""
    return rrb.Blueprint(
        rrb.Horizontal(
            rrb.Spatial3DView(origin=f"/{WORLD}", name="workcell"),
            rrb.Vertical(
                rrb.TimeSeriesView(origin=f"/{JOINTS}", name="joints"),
                rrb.TimeSeriesView(origin=f"/{HANDS}", name="grip, trigger, gripper"),
                rrb.Tabs(
                    rrb.TextLogView(origin=f"/{EVENTS_ENTITY}", name="events"),
                    rrb.TextDocumentView(origin=f"/{PROVENANCE_ENTITY}", name="provenance"),
                ),
            ),
            column_shares=[3, 2],
        ),
        rrb.TimePanel(timeline=TIME_TIMELINE),
    )


def log_trial(stream: rr.RecordingStream, trial: TrialRecording) -> None:
    """Log everything of ``trial`` to ``stream`` (whose sink is already set)."""
    stream.send_recording_name(f"trial {trial.provenance.trial_id}")
    stream.send_recording_start_time_nanos(round(trial.started_wall * 1e9))
    _log_static(stream, trial)
    frames = trial.frames
    indexes = _frame_indexes(frames)
    _log_path(stream, "base", _base_positions(frames), BASE_COLOR)
    _send(stream, BASE_ENTITY, indexes, _base_transforms(frames))
    for tcp in TCPS:
        positions = _xyz(frames, tcp)
        _log_path(stream, tcp, positions, TCP_COLORS[tcp])
        _send(stream, tcp_entity(tcp), indexes, _points(positions, TCP_COLORS[tcp]))
    _log_box_shapes(stream, trial)
    _send(stream, BOXES_ENTITY, indexes, _boxes(trial))
    scalars = {joint_entity(joint): frames[f"q_{joint}"] for joint in JOINT_ORDER}
    scalars |= {hand_entity(column): frames[column] for column in HAND_COLUMNS}
    for entity, values in scalars.items():
        _send(stream, entity, indexes, rr.Scalars.columns(scalars=values))
    _log_events(stream, trial)


def provenance_values(provenance: Provenance) -> rr.AnyValues:
    """Every Provenance field as a typed component: one value, null when not recorded
    (``quality_flags``: one string per flag, possibly none)."""
    hints = typing.get_type_hints(Provenance)
    values = {}
    for name, value in provenance.as_dict().items():
        arrow_type = _arrow_type(hints[name])
        items = value if isinstance(value, list) else [value]
        values[name] = pa.array(items, arrow_type)
    return rr.AnyValues(**values)


def event_text(event: EventRecord) -> str:
    """``box_delivered: box=0, boxes_delivered=1`` (the payload's values as JSON)."""
    fields = ", ".join(
        f"{key}={json.dumps(value)}" for key, value in event.payload.items() if key != "trial_index"
    )
    return f"{event.kind}: {fields}" if fields else event.kind


_ARROW_TYPES: dict[object, Any] = {
    str: pa.string(),
    int: pa.int64(),
    float: pa.float64(),
    bool: pa.bool_(),
}


def _arrow_type(hint: object) -> Any:
    """The Arrow type of a Provenance field: ``int | None`` → int64, ``tuple[str, ...]`` →
    string, ..."""
    args = [arg for arg in typing.get_args(hint) if arg is not type(None)]
    return _ARROW_TYPES[args[0] if args else hint]


def _log_static(stream: rr.RecordingStream, trial: TrialRecording) -> None:
    stream.log("/", provenance_values(trial.provenance), static=True, strict=True)
    p = trial.provenance
    step = "" if p.study_step is None else f", study step {p.study_step}"
    condition = "" if p.condition is None else f", condition {p.condition}"
    markdown = (
        f"# Trial {p.trial_id}\n\n"
        f"operator {p.operator_id}{condition}{step}; {p.outcome}\n\n"
        f"{p.task}\n\n"
        f"```json\n{json.dumps(trial.document, indent=2)}\n```\n"
    )
    stream.log(
        PROVENANCE_ENTITY,
        rr.TextDocument(markdown, media_type=rr.MediaType.MARKDOWN),
        static=True,
        strict=True,
    )
    stream.log(WORLD, rr.ViewCoordinates.RIGHT_HAND_Z_UP, static=True, strict=True)
    # Only the axis length is static: a static translation or rotation would hide the
    # per-frame ones.
    stream.log(
        BASE_ENTITY, rr.Transform3D.from_fields(axis_length=AXIS_LENGTH), static=True, strict=True
    )


def _send(
    stream: rr.RecordingStream,
    entity: str,
    indexes: Sequence[rr.TimeColumn],
    columns: rr.ComponentColumnList,
) -> None:
    stream.send_columns(entity, indexes=indexes, columns=columns, strict=True)


def _frame_indexes(frames: Mapping[str, NDArray[Any]]) -> list[rr.TimeColumn]:
    return [
        rr.TimeColumn(FRAME_TIMELINE, sequence=frames["frame_index"].astype(np.int64)),
        rr.TimeColumn(TIME_TIMELINE, duration=_nanoseconds(frames["t_sim"])),
    ]


def _nanoseconds(seconds: NDArray[np.float64]) -> NDArray[np.timedelta64]:
    """Seconds as whole nanoseconds, rounded (rerun's own conversion truncates)."""
    return np.rint(np.asarray(seconds, dtype=np.float64) * 1e9).astype("timedelta64[ns]")


def _xyz(frames: Mapping[str, NDArray[Any]], prefix: str) -> NDArray[np.float64]:
    return np.column_stack([frames[f"{prefix}_{axis}"] for axis in "xyz"]).astype(np.float64)


def _base_positions(frames: Mapping[str, NDArray[Any]]) -> NDArray[np.float64]:
    x, y = frames["base_x"], frames["base_y"]
    return np.column_stack([x, y, np.zeros_like(x)]).astype(np.float64)


def _log_path(
    stream: rr.RecordingStream, name: str, positions: NDArray[np.float64], color: tuple[int, ...]
) -> None:
    stream.log(
        trajectory_entity(name),
        rr.LineStrips3D([positions], radii=PATH_RADIUS, colors=[color]),
        static=True,
        strict=True,
    )


def _points(positions: NDArray[np.float64], color: tuple[int, ...]) -> rr.ComponentColumnList:
    n = len(positions)
    return rr.Points3D.columns(
        positions=positions,
        radii=np.full(n, TCP_RADIUS, dtype=np.float32),
        colors=np.full(n, packed_rgba(color), dtype=np.uint32),
    )


def packed_rgba(colors: Sequence[int] | NDArray[Any]) -> NDArray[np.uint32]:
    """RGBA colours (0-255, last axis of 4) as rerun's packed 0xRRGGBBAA integers.

    Columns of colours must be packed: given an (n, 4) uint8 array, rerun-sdk 0.26's
    ``send_columns`` counts 4n colours and fails.
    """
    rgba = np.asarray(colors, dtype=np.uint32)
    shifted = rgba << np.array([24, 16, 8, 0], dtype=np.uint32)
    packed: NDArray[np.uint32] = np.bitwise_or.reduce(shifted, axis=-1).astype(np.uint32)
    return packed


def _base_transforms(frames: Mapping[str, NDArray[Any]]) -> rr.ComponentColumnList:
    half = np.asarray(frames["base_yaw"], dtype=np.float64) / 2
    zeros = np.zeros_like(half)
    quaternions = np.column_stack([zeros, zeros, np.sin(half), np.cos(half)])  # x, y, z, w
    return rr.Transform3D.columns(translation=_base_positions(frames), quaternion=quaternions)


def _log_box_shapes(stream: rr.RecordingStream, trial: TrialRecording) -> None:
    """The pool's sizes, names and fill mode: the same at every frame."""
    pool = trial.boxes.pool_size
    stream.log(
        BOXES_ENTITY,
        rr.Boxes3D.from_fields(
            half_sizes=np.asarray([look.size for look in trial.box_looks], dtype=np.float64) / 2,
            labels=[f"box{i}" for i in range(pool)],
            fill_mode=rr.components.FillMode.Solid,
        ),
        static=True,
        strict=True,
    )


def _boxes(trial: TrialRecording) -> rr.ComponentColumnList:
    """Every box's pose and state colour at every frame."""
    boxes = trial.boxes
    n, pool = boxes.states.shape
    poses = boxes.poses.reshape(n * pool, 7)
    # (box, state) -> colour: parked and delivered alike for every box, active its own
    palette = np.zeros((pool, len(BOX_STATE_CODES), 4), dtype=np.uint8)
    palette[:, BOX_STATE_CODES["parked"]] = PARKED_COLOR
    palette[:, BOX_STATE_CODES["active"]] = np.round(
        np.asarray([look.rgba for look in trial.box_looks]) * 255
    )
    palette[:, BOX_STATE_CODES["delivered"]] = DELIVERED_COLOR
    colors = packed_rgba(palette.reshape(-1, 4)).reshape(pool, len(BOX_STATE_CODES))
    return rr.Boxes3D.columns(
        centers=poses[:, :3],
        quaternions=poses[:, [4, 5, 6, 3]],  # recorded w, x, y, z → rerun's x, y, z, w
        colors=colors[np.arange(pool)[None, :], boxes.states].reshape(-1),
    ).partition(np.full(n, pool))


def _log_events(stream: rr.RecordingStream, trial: TrialRecording) -> None:
    if not trial.events:
        return
    # a trial's events always carry its sim time; None would be a session event
    times = np.array([e.t_sim if e.t_sim is not None else 0.0 for e in trial.events])
    recorded = np.asarray(trial.frames["t_sim"], dtype=np.float64)
    at = np.clip(np.searchsorted(recorded, times, side="right") - 1, 0, None)
    frames = np.asarray(trial.frames["frame_index"], dtype=np.int64)[at]
    indexes = [
        rr.TimeColumn(FRAME_TIMELINE, sequence=frames),
        rr.TimeColumn(TIME_TIMELINE, duration=_nanoseconds(times)),
        rr.TimeColumn(EVENT_TIMELINE, sequence=np.arange(len(trial.events), dtype=np.int64)),
    ]
    columns = rr.TextLog.columns(
        text=[event_text(e) for e in trial.events],
        level=["WARN" if e.kind in WARNING_EVENTS else "INFO" for e in trial.events],
    )
    _send(stream, EVENTS_ENTITY, indexes, columns)

"""How far a trial got, read from its recorded frames: the furthest stage of the task any
of its boxes reached (the stages are the task's:
:mod:`workcell.tasks.box_transfer.stages`, where the live judge reads them too).

A trial that times out may have done everything but the last step, or nothing at all; its
outcome alone cannot tell a policy that never moved from one that carried the box to the
table and never let go. The stage can: it is read from the frames the record already holds
(the grippers' contacts, the grasp, every box's pose) and from the trial's target zone.
"""

from __future__ import annotations

import json
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from workcell.sim.config import TargetConfig
from workcell.tasks.box_transfer.stages import (
    LIFT_M,
    TASK_STAGES,
    TASK_STAGES_VERSION,
    Hold,
    StageTracker,
    TaskStage,
    Zone,
)

__all__ = [
    "LIFT_M",
    "TASK_STAGES",
    "TASK_STAGES_VERSION",
    "Hold",
    "StageFrames",
    "TaskStage",
    "Zone",
    "stage_reached",
]

FRAMES_TASK = "box_transfer"
"""The task whose stages the frames define here (``BoxTransfer.name``; named, not imported,
so that an audit loads no physics)."""


def session_task(parameters: Mapping[str, Any]) -> str:
    """The ``task.kind`` a session's ``parameters`` name, read as
    :func:`workcell.tasks.registry.recorded_kind` reads it (box transfer for a store written
    before sessions named their task), without loading any task."""
    task = parameters.get("task")
    kind = task.get("kind", FRAMES_TASK) if isinstance(task, Mapping) else FRAMES_TASK
    return str(kind)


STAGE_COLUMNS: tuple[str, ...] = ("frame_index", "contact_l", "contact_r", "attached", "boxes")
"""The frame columns the stage is read from."""
SIGNALS_SQL = (
    "SELECT coalesce(max(contact_l >= 0 OR contact_r >= 0), 0), coalesce(max(attached >= 0), 0) "
    "FROM frames WHERE trial_id = ?"
)
"""Whether a trial's frames show a touch and a grasp, counted inside SQLite."""
HOLDS_SQL = (
    "SELECT frame_index, attached, json_extract(boxes, '$[' || attached || '][0]', "
    "'$[' || attached || '][2]', '$[' || attached || '][3]', '$[' || attached || '][4]') "
    "FROM frames WHERE trial_id = ? AND attached >= 0 ORDER BY frame_index"
)
"""Every frame of a trial that holds a box: (frame_index, box, the JSON text ``[index, x, y,
z]`` of the ``boxes`` entry at the box's position), parsed inside SQLite (the ``boxes`` list
holds every box of the pool in index order; :func:`holds_from_sql` checks the index). SQLite
refuses the whole query when one ``boxes`` cell is not JSON: read such a trial with
:data:`STAGE_COLUMNS` and :func:`stage_frames` instead."""


@dataclass(frozen=True)
class StageFrames:
    """What the frames say about a trial's progress: whether a gripper touched a box,
    whether one was held, and every frame in which a held box's position is known, in frame
    order."""

    touched: bool
    grasped: bool
    holds: tuple[Hold, ...]


NO_STAGE_FRAMES = StageFrames(touched=False, grasped=False, holds=())
"""A trial without frames: nothing touched, nothing held."""


def session_zone(parameters: Mapping[str, Any]) -> Zone:
    """The target zone a session's ``parameters`` configure (the declared default where
    they hold none)."""
    world = parameters.get("world")
    target = world.get("target") if isinstance(world, Mapping) else None
    default = TargetConfig()
    center, size = default.center, default.zone
    if isinstance(target, Mapping):
        center = _pair(target.get("center"), center)
        size = _pair(target.get("zone"), size)
    return Zone(center, size)


def trial_zone(session: Zone, conditions: Mapping[str, Any] | None) -> Zone:
    """The zone of one trial: the session's, centred where the trial's recorded conditions
    put the target (randomized worlds move it)."""
    if conditions is None:
        return session
    return Zone(_pair(conditions.get("target_center"), session.center), session.size)


def _pair(value: object, default: tuple[float, float]) -> tuple[float, float]:
    if isinstance(value, Sequence) and len(value) == 2:
        try:
            return float(value[0]), float(value[1])
        except (TypeError, ValueError):
            return default
    return default


def started_conditions(payload: str) -> dict[str, object]:
    """The ``conditions`` of a trial_started event's JSON payload ({} when unreadable)."""
    try:
        conditions = json.loads(payload).get("conditions")
    except (ValueError, AttributeError):
        return {}
    return conditions if isinstance(conditions, dict) else {}


def stage_frames(rows: Iterable[Sequence[object]]) -> StageFrames:
    """Read ``STAGE_COLUMNS`` rows (NULL as None, ``boxes`` as its JSON text) into the
    touches and holds of one trial. Rows whose grasp signals are missing or unreadable
    raise nothing: they simply cannot raise the stage."""
    touched = grasped = False
    holds: list[Hold] = []
    for frame_index, contact_l, contact_r, attached, boxes in rows:
        if _index(contact_l) >= 0 or _index(contact_r) >= 0:
            touched = True
        box = _index(attached)
        if box < 0:
            continue
        grasped = True
        position = _box_position(boxes, box) if isinstance(boxes, str) else None
        if position is not None:
            holds.append(Hold(int(_index(frame_index)), box, *position))
    return StageFrames(touched or grasped, grasped, tuple(holds))


BoxesOf = Callable[[int], "str | None"]
"""The ``boxes`` JSON of one frame of the trial, by frame index."""


def holds_from_sql(
    signals: Sequence[object], rows: Iterable[Sequence[object]], boxes_of: BoxesOf
) -> StageFrames:
    """A trial's touches and holds from :data:`SIGNALS_SQL`'s row and :data:`HOLDS_SQL`'s
    rows; a hold whose ``boxes`` entry is not at its index is read whole (``boxes_of``)."""
    touched, grasped = (bool(v) for v in signals)
    holds: list[Hold] = []
    for frame_index, attached, extracted in rows:
        box = _index(attached)
        position = _entry_position(extracted, box)
        if position is None:
            boxes = boxes_of(int(_index(frame_index)))
            position = _box_position(boxes, box) if boxes is not None else None
        if position is not None:
            holds.append(Hold(int(_index(frame_index)), box, *position))
    return StageFrames(touched or grasped, grasped, tuple(holds))


def _entry_position(extracted: object, box: int) -> tuple[float, float, float] | None:
    if not isinstance(extracted, str):
        return None
    try:
        index, x, y, z = json.loads(extracted)
        position = float(x), float(y), float(z)
    except (ValueError, TypeError):
        return None
    if index != box or not np.isfinite(position).all():
        return None
    return position


def _index(value: object) -> int:
    """A grasp signal as an int: -1 for none, NULL, NaN or text that is not a number."""
    if value is None or value == "":
        return -1
    try:
        number = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        return -1
    return int(number) if np.isfinite(number) else -1


def _box_position(boxes: str, box: int) -> tuple[float, float, float] | None:
    try:
        entries = json.loads(boxes)
    except ValueError:
        return None
    for entry in entries if isinstance(entries, list) else ():
        if isinstance(entry, list) and len(entry) >= 5 and entry[0] == box:
            x, y, z = (float(v) for v in entry[2:5])
            if np.isfinite([x, y, z]).all():
                return x, y, z
    return None


def stage_reached(frames: StageFrames, zone: Zone, completed: int | None) -> TaskStage:
    """The furthest stage of :data:`TASK_STAGES` the trial reached (``completed``: the
    boxes it finished, :data:`~workcell.tasks.box_transfer.stages.COMPLETED_COLUMN`)."""
    tracker = StageTracker(zone)
    if frames.touched:
        tracker.touch()
    if frames.grasped:
        tracker.grasp()
    for hold in frames.holds:
        tracker.hold(hold)
    return tracker.stage(completed)


def stage_counts(stages: Iterable[str], order: Sequence[str] = TASK_STAGES) -> dict[str, int]:
    """How many trials ended at each stage, every stage of ``order`` (a task's stages,
    box transfer's by default) named in that order; a stage outside it follows them."""
    counts: dict[str, int] = dict.fromkeys(order, 0)
    for stage in stages:
        counts[stage] = counts.get(stage, 0) + 1
    return counts


def counts_text(counts: Mapping[str, int]) -> str:
    """The stages trials ended at, furthest first, none left out but zeros:
    ``18 settled, 2 placed_3``."""
    parts = [f"{n} {stage}" for stage, n in reversed(list(counts.items())) if n]
    return ", ".join(parts) or "no trials"


def at_least(counts: Mapping[str, int]) -> dict[str, int]:
    """How many trials reached each stage or a later one, the stages in ``counts``'s
    order (:func:`stage_counts`: a trial at a task's last stage also reached each
    stage before it)."""
    total = 0
    out: dict[str, int] = {}
    for stage in reversed(list(counts)):
        total += counts[stage]
        out[stage] = total
    return {stage: out[stage] for stage in counts}

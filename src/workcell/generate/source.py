"""Source trials: the recorded motion a generation replays, read from a store.

Only what replay needs is kept, per frame: the trial clock, the base's pose and commanded
twist, both arms' TCP targets (base frame), follow flags and gripper commands, the head
command, the task's stage, which box the hands held, and the pose of every box the trial
grasped; with where the trial's goal sites were (:meth:`workcell.tasks.Task.goal_sites`: box
transfer's target zone's centre, shelve's asked board and its height, palletize's four
slots and the pallet's turn). A source trial is a successful trial of the
task; failed, timed-out and interrupted trials are not replayed.
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from workcell.generate.errors import GenerateError
from workcell.generate.planar import yaw_of
from workcell.record.columns import pose_columns
from workcell.record.entries import EventRecord
from workcell.tasks.task import GoalSite, ObjectLook, Task

NO_BOX = -1


@dataclass(frozen=True)
class SourceTrial:
    """One recorded trial's motion (arrays of one row per frame)."""

    trial_id: str
    operator_id: str
    t: NDArray[np.float64]
    base: NDArray[np.float64]
    """(n, 3): x, y, yaw in the world."""
    twist: NDArray[np.float64]
    """(n, 3): the commanded base twist (base frame)."""
    targets: NDArray[np.float64]
    """(n, 2, 7): left and right TCP targets in the base frame (x, y, z, qw, qx, qy, qz)."""
    follow: NDArray[np.bool_]
    """(n, 2): whether each arm followed its target."""
    close: NDArray[np.float64]
    """(n, 2): each gripper's commanded closing, 0 open .. 1 closed."""
    head: NDArray[np.float64]
    """(n, 2): head pan and tilt commanded."""
    stage: tuple[str, ...]
    """Each frame's stage, as the task's judge said."""
    box: int
    """The index of the box the trial grasped first."""
    attached: NDArray[np.int64]
    """(n,): the box the hands held at each frame (:data:`NO_BOX`: none)."""
    box_poses: Mapping[int, NDArray[np.float64]]
    """For each box the trial grasped, (n, 4): its x, y, yaw and speed (m/s) at each frame
    (NaN where not active)."""
    sites: tuple[GoalSite, ...]
    """Where the trial's objects went (the task's :meth:`~workcell.tasks.Task.goal_sites`)."""
    key: tuple[float, ...]
    """What an attempt replaying it should share with it (the task's
    :meth:`~workcell.tasks.Task.source_key`)."""
    box_sizes: Mapping[int, tuple[float, float, float]]
    """The sides (m) of each box the trial grasped, as its conditions recorded them (NaN
    where they did not)."""

    def __len__(self) -> int:
        return len(self.t)

    @property
    def box_pose(self) -> NDArray[np.float64]:
        """(n, 4): the pose and speed of the box the trial grasped first."""
        return self.box_poses[self.box]


def load_sources(store: Path, task: str, operators: Sequence[str] = ()) -> tuple[SourceTrial, ...]:
    """The successful trials of ``task`` in ``store`` (only those of ``operators``, when
    given), in recording order; a GenerateError saying what is missing otherwise."""
    from workcell.record.store import Store  # noqa: PLC0415
    from workcell.tasks.registry import load_task, recorded_kind  # noqa: PLC0415

    if not store.is_file():
        raise GenerateError(f"--source {store}: no such store (record source trials first)")
    with Store.open(store, writer=False) as reader:
        sessions = {s.session_id: s for s in reader.sessions()}
        trials = reader.trials()
        if not trials:
            raise GenerateError(f"--source {store}: the store holds no trials")
        kinds = sorted({recorded_kind(s.parameters) for s in sessions.values()})
        chosen = [
            t
            for t in trials
            if recorded_kind(sessions[t.session_id].parameters) == task
            and (not operators or sessions[t.session_id].operator_id in operators)
        ]
        if not chosen:
            whose = f" by operator {', '.join(operators)}" if operators else ""
            who = sorted({s.operator_id for s in sessions.values()})
            raise GenerateError(
                f"--source {store}: no trials of task {task}{whose}; it holds trials of "
                f"{', '.join(kinds)} by {', '.join(who)}"
            )
        successes = [t for t in chosen if t.outcome == "success" and t.n_frames]
        if not successes:
            raise GenerateError(
                f"--source {store}: none of its {len(chosen)} trials of {task} succeeded; "
                "generation replays successful trials only"
            )
        kind = load_task(task)
        return tuple(
            _source(
                kind,
                t.trial_id,
                sessions[t.session_id].operator_id,
                reader.frames(t.trial_id),
                t.goal,
                _conditions(reader.events(t.trial_id)),
            )
            for t in successes
        )


def _goal(
    task: Task, trial_id: str, goal: dict[str, Any] | None
) -> tuple[tuple[GoalSite, ...], tuple[float, ...]]:
    """A source trial's goal sites and source key, from the goal its trial row recorded."""
    names = task.goal_names
    numbers = [float((goal or {}).get(name, math.nan)) for name in names]
    sites = task.goal_sites(numbers) if numbers else ()
    values = [v for site in sites for v in (site.x, site.y, site.yaw, site.height)]
    if not sites or not all(math.isfinite(v) for v in values):
        raise GenerateError(
            f"source trial {trial_id}: its goal ({', '.join(names)}) is not recorded"
        )
    return sites, task.source_key(numbers)


def _conditions(events: Sequence[EventRecord]) -> dict[str, Any]:
    """The conditions the trial's ``trial_started`` recorded ({} where none)."""
    for event in events:
        if event.kind == "trial_started":
            conditions = event.payload.get("conditions")
            return conditions if isinstance(conditions, dict) else {}
    return {}


def _box_sizes(
    task: Task, conditions: dict[str, Any], boxes: Sequence[int]
) -> dict[int, tuple[float, float, float]]:
    """The sides of each of ``boxes`` as the trial's conditions recorded them (the task's
    :meth:`~workcell.tasks.Task.object_looks`: sort's two kinds differ), NaN where not."""
    size, rgba = conditions.get("box_size"), conditions.get("box_rgba")
    if not (isinstance(size, list) and len(size) == 3):
        return {box: (math.nan, math.nan, math.nan) for box in boxes}
    if not (isinstance(rgba, list) and len(rgba) == 4):
        rgba = [1.0, 1.0, 1.0, 1.0]
    trial_box = ObjectLook(
        (float(size[0]), float(size[1]), float(size[2])),
        (float(rgba[0]), float(rgba[1]), float(rgba[2]), float(rgba[3])),
    )
    looks = task.object_looks(conditions, max(boxes) + 1, trial_box)
    return {box: looks[box].size for box in boxes}


def _source(  # noqa: PLR0917 - a trial's parts
    task: Task,
    trial_id: str,
    operator_id: str,
    frames: dict[str, NDArray[Any]],
    goal: dict[str, Any] | None,
    conditions: dict[str, Any],
) -> SourceTrial:
    n = len(frames["t_sim"])
    targets = np.stack(
        [
            np.stack([frames[c] for c in pose_columns("target_l")], axis=1),
            np.stack([frames[c] for c in pose_columns("target_r")], axis=1),
        ],
        axis=1,
    ).astype(np.float64)
    attached = np.asarray(frames["attached"], dtype=np.int64)
    held = attached[attached >= 0]
    if not len(held):
        raise GenerateError(f"source trial {trial_id}: succeeded without grasping a box")
    box = int(held[0])
    sites, key = _goal(task, trial_id, goal)
    poses = {int(b): np.full((n, 4), np.nan) for b in np.unique(held)}
    for i, text in enumerate(frames["boxes"]):
        for entry in json.loads(text):
            pose = poses.get(int(entry[0]))
            if pose is not None and entry[1] != "parked":
                pose[i, :3] = (entry[2], entry[3], yaw_of(entry[5:9]))
    t = np.asarray(frames["t_sim"], dtype=np.float64)
    for box_pose in poses.values():
        step = np.diff(box_pose[:, :2], axis=0) / np.maximum(np.diff(t), 1e-9)[:, None]
        box_pose[1:, 3] = np.linalg.norm(step, axis=1)
        box_pose[0, 3] = box_pose[1, 3] if n > 1 else np.nan
    return SourceTrial(
        trial_id=trial_id,
        operator_id=operator_id,
        t=t,
        base=np.stack([frames["base_x"], frames["base_y"], frames["base_yaw"]], axis=1).astype(
            np.float64
        ),
        twist=np.stack([frames["cmd_vx"], frames["cmd_vy"], frames["cmd_wz"]], axis=1).astype(
            np.float64
        ),
        targets=targets,
        follow=np.stack([frames["follow_l"], frames["follow_r"]], axis=1).astype(bool),
        close=np.stack([frames["gripper_cmd_l"], frames["gripper_cmd_r"]], axis=1).astype(
            np.float64
        ),
        head=np.stack([frames["head_cmd_pan"], frames["head_cmd_tilt"]], axis=1).astype(np.float64),
        stage=tuple(str(s) for s in frames["stage"]),
        box=box,
        attached=attached,
        box_poses=poses,
        sites=sites,
        key=key,
        box_sizes=_box_sizes(task, conditions, sorted(poses)),
    )

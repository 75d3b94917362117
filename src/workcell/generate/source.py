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
from workcell.tasks.task import GoalSite, Task

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
    box_size: tuple[float, float, float]
    """The sides of the trial's boxes (m), as its conditions recorded them."""

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
        goal_of = _GoalSite(load_task(task))
        return tuple(
            _source(
                t.trial_id,
                sessions[t.session_id].operator_id,
                reader.frames(t.trial_id),
                goal_of(t.trial_id, t.goal),
                _box_size(reader.events(t.trial_id)),
            )
            for t in successes
        )


class _GoalSite:
    """A source trial's goal sites, from the goal its trial row recorded."""

    def __init__(self, task: Task) -> None:
        self.task = task

    def __call__(self, trial_id: str, goal: dict[str, Any] | None) -> tuple[GoalSite, ...]:
        names = self.task.goal_names
        numbers = [float((goal or {}).get(name, math.nan)) for name in names]
        sites = self.task.goal_sites(numbers) if numbers else ()
        values = [v for site in sites for v in (site.x, site.y, site.yaw, site.height)]
        if not sites or not all(math.isfinite(v) for v in values):
            raise GenerateError(
                f"source trial {trial_id}: its goal ({', '.join(names)}) is not recorded"
            )
        return sites


def _box_size(events: Sequence[EventRecord]) -> tuple[float, float, float]:
    for event in events:
        if event.kind == "trial_started":
            size = event.payload.get("conditions", {}).get("box_size")
            if isinstance(size, list) and len(size) == 3:
                return float(size[0]), float(size[1]), float(size[2])
    return (math.nan, math.nan, math.nan)


def _source(
    trial_id: str,
    operator_id: str,
    frames: dict[str, NDArray[Any]],
    sites: tuple[GoalSite, ...],
    box_size: tuple[float, float, float],
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
        box_size=box_size,
    )

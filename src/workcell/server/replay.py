"""``GET /api/trials/{id}/frames``: a recorded trial as the poses of the scene's bodies.

The recorded base pose, 17 joints, gripper openings and boxes are put into a world built
with the session's own parameters and set to the trial's own start from its recorded seed
(a D1/D2 trial's pallet, shelf or tables where that trial had them, its box size and
target), and forward kinematics gives every dynamic body's
world pose, so the client replays with the same code that draws a live State. Beside
them go the trial's facts and event timeline (:mod:`workcell.server.replay_facts`).
"""

from __future__ import annotations

import json
import math
from typing import Any

import mujoco
import numpy as np
from numpy.typing import NDArray

from workcell.errors import ConfigError, WorkcellError
from workcell.protocol.api import TrialReplay
from workcell.protocol.scene import Pose
from workcell.record.store import Store
from workcell.server.replay_facts import replay_facts, timeline
from workcell.server.scene import PoseReader, describe
from workcell.session.config import SessionConfig
from workcell.session.toml_io import from_mapping
from workcell.sim.joints import BASE_JOINTS, FINGER_JOINTS, JOINT_ORDER, SIDES
from workcell.sim.trial_start import start_trial
from workcell.sim.world import World
from workcell.tasks.registry import load_task

MAX_FRAMES = 20_000
"""Most frames one reply carries (``every`` is raised to stay under it)."""


class TrialNotFoundError(WorkcellError):
    """No such trial in the store."""


def _config(parameters: dict[str, Any]) -> SessionConfig:
    try:
        return from_mapping(SessionConfig, parameters)
    except ConfigError:  # recorded by another version: draw with today's defaults
        return SessionConfig()


def _qpos_indices(model: mujoco.MjModel, names: tuple[str, ...]) -> NDArray[np.int64]:
    return np.array([model.jnt_qposadr[model.joint(n).id] for n in names], dtype=np.int64)


def trial_replay(store: Store, trial_id: str, every: int) -> TrialReplay:
    trials = [t for t in store.trials() if t.trial_id == trial_id]
    if not trials:
        raise TrialNotFoundError(f"trial {trial_id[:64]!r} is not in the store")
    trial = trials[0]
    session = next(s for s in store.sessions() if s.session_id == trial.session_id)
    config = _config(session.parameters)
    world = World(config.world, load_task(config.task.kind).scene())
    model, data = world.model, world.data
    if trial.trial_seed is not None:  # the trial's own world: where its scene put things
        start_trial(world, np.zeros(len(JOINT_ORDER)), trial.trial_seed)
    mujoco.mj_kinematics(model, data)
    frames = store.frames(trial_id)
    count = len(frames["t_sim"])
    every = max(every, math.ceil(count / MAX_FRAMES))
    base = _qpos_indices(model, BASE_JOINTS)
    joints = _qpos_indices(model, JOINT_ORDER)
    fingers = {s: _qpos_indices(model, FINGER_JOINTS[s]) for s in SIDES}
    finger_open = float(model.jnt_range[model.joint(FINGER_JOINTS["l"][0]).id][1])
    box_rows = world.boxes.pose_indices
    reader = PoseReader(model)
    q_columns = np.stack([frames[f"q_{j}"] for j in JOINT_ORDER], axis=1)
    times: list[float] = []
    poses: list[tuple[Pose, ...]] = []
    for i in range(0, count, every):
        data.qpos[base] = (frames["base_x"][i], frames["base_y"][i], frames["base_yaw"][i])
        data.qpos[joints] = np.nan_to_num(q_columns[i])
        for side in SIDES:
            opening = float(np.nan_to_num(frames[f"gripper_{side}"][i], nan=1.0))
            data.qpos[fingers[side]] = opening * finger_open
        for index, _state, *pose in json.loads(str(frames["boxes"][i]) or "[]"):
            if 0 <= index < len(box_rows):
                data.qpos[box_rows[index]] = pose
        mujoco.mj_kinematics(model, data)
        times.append(round(float(frames["t_sim"][i]), 6))
        poses.append(reader.poses(data))
    return TrialReplay(
        trial_id=trial_id,
        session_id=trial.session_id,
        every=every,
        scene=describe(model, data),
        t_sim=tuple(times),
        poses=tuple(poses),
        recorded_frames=count,
        facts=replay_facts(store, session, trial),
        events=timeline(store.events(trial_id)),
    )

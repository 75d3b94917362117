"""The replay check: restoring the recorded states must reproduce the recorded poses.

Both TCP poses are recomputed from the restored joints by ``mj_forward`` and compared
with the recorded ``tcp_*`` columns. A mismatch means the world model differs from the one
that recorded the trial (another software version or configuration), so renders of it
would not show what happened.

The recorder reads site poses right after ``mj_step``, when MuJoCo still holds the
kinematics computed *before* the step's integration: those ``tcp_*`` are one physics step
older than the recorded joints. The check therefore also restores each frame one step back
along the recorded velocities (exact for MuJoCo's integrators) and reports the lag that
reproduces the poses: 1 for such stores, 0 for a recorder that refreshes the kinematics.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import mujoco
import numpy as np
from numpy.typing import NDArray

from workcell.export.boxes import parse_boxes
from workcell.export.errors import UnknownTrialError
from workcell.export.restore import RecordedStates, StateRestorer
from workcell.export.source import session_config
from workcell.record.store import Store
from workcell.sim.joints import SIDES
from workcell.sim.world import World
from workcell.tasks.registry import load_task

TCP_TOLERANCE_M = 1e-6
"""Largest TCP position error (m) the replay check accepts."""
TCP_TOLERANCE_RAD = 1e-6
"""Largest TCP orientation error (rad) the replay check accepts."""
LAGS = (0, 1)
"""Physics steps between the recorded joints and the recorded TCP poses that are tried."""


@dataclass(frozen=True)
class ReplayErrors:
    """The largest TCP errors over a trial's frames, both arms, at one lag."""

    position_m: float = 0.0
    angle_rad: float = 0.0
    lag_steps: int = 0

    @property
    def within_tolerance(self) -> bool:
        return self.position_m <= TCP_TOLERANCE_M and self.angle_rad <= TCP_TOLERANCE_RAD

    def worst(self, other: ReplayErrors) -> ReplayErrors:
        return ReplayErrors(
            max(self.position_m, other.position_m),
            max(self.angle_rad, other.angle_rad),
            self.lag_steps,
        )


def rotation_angle(a: NDArray[np.float64], b: NDArray[np.float64]) -> float:
    """Angle (rad) of the rotation between unit quaternions ``a`` and ``b`` (w, x, y, z)."""
    relative = np.zeros(4)
    conjugate = np.zeros(4)
    mujoco.mju_negQuat(conjugate, a)
    mujoco.mju_mulQuat(relative, conjugate, b)
    return 2.0 * math.atan2(float(np.linalg.norm(relative[1:])), abs(float(relative[0])))


def frame_errors(restorer: StateRestorer, states: RecordedStates, i: int, lag: int) -> ReplayErrors:
    """TCP errors of frame ``i``, which must just have been restored (with forward)."""
    position = angle = 0.0
    for side_index, side in enumerate(SIDES):
        xyz, quat = restorer.world.tcp_pose(side)
        recorded = states.tcp[i, side_index]
        position = max(position, float(np.linalg.norm(xyz - recorded[:3])))
        angle = max(angle, rotation_angle(quat, recorded[3:]))
    return ReplayErrors(position, angle, lag)


def replay_errors(world: World, states: RecordedStates) -> ReplayErrors:
    """Restore every frame into ``world``; the largest TCP errors at the best lag."""
    restorer = StateRestorer(world)
    results = []
    for lag in LAGS:
        errors = ReplayErrors(lag_steps=lag)
        for i in range(len(states)):
            restorer.restore(states, i, back_steps=lag)
            errors = errors.worst(frame_errors(restorer, states, i, lag))
        results.append(errors)
    return min(results, key=lambda e: (e.position_m, e.angle_rad))


def replay_check(store: Store, trial_id: str) -> float:
    """Largest TCP position error (m) when the trial's recorded states are restored (at the
    lag that reproduces them best; see the module documentation)."""
    trial = next((t for t in store.trials() if t.trial_id == trial_id), None)
    if trial is None:
        raise UnknownTrialError(
            f"no trial {trial_id} in store {store.path}; 'workcell export --format csv' "
            "lists the trials in trials.csv"
        )
    session = next(s for s in store.sessions() if s.session_id == trial.session_id)
    config = session_config(session)
    world = World(config.world, load_task(config.task.kind).scene())
    frames = store.frames(trial_id)
    boxes = parse_boxes(frames["boxes"], config.world.feeder.pool_size)
    states = RecordedStates.from_frames(frames, boxes)
    return replay_errors(world, states).position_m

"""The simulated workcell: physics, the box feeder and grasping, and the task's scene.

The world knows nothing about operators; :class:`workcell.simulation.Simulation` drives it
with commands through the robot controller. What a task adds to the shared factory and
watches in it each control period (box transfer: a released box resting in the target
zone is done) is the task's :class:`TaskScene` (:mod:`workcell.tasks`).
"""

from __future__ import annotations

import math
from typing import Protocol

import mujoco
import numpy as np
from numpy.typing import NDArray

from workcell.errors import SimulationError
from workcell.sim.boxes import BoxPool, BoxSlot, BoxState
from workcell.sim.conditions import apply_conditions
from workcell.sim.config import WorldConfig
from workcell.sim.events import BoxReleased, GraspChanged, WorldEvent
from workcell.sim.grasp import Grasp
from workcell.sim.joints import BASE_JOINTS, FINGER_JOINTS, JOINT_ORDER, SIDES
from workcell.sim.scene import build_world_model
from workcell.sim.target import TargetZone
from workcell.sim.trial_conditions import TrialConditions

FLOOR_CLEAR_S = 5.0
"""A box lying on the floor is taken away after this long."""


class Sampler(Protocol):
    """Something that samples the world at exact physics steps (the recorder)."""

    @property
    def next_step(self) -> int:
        """The physics step count at which the next sample is due."""
        ...

    def sample(self) -> None:
        """Take the sample due now; advances :attr:`next_step`."""
        ...


class TaskScene(Protocol):
    """What a task adds to the shared factory and watches in it (:mod:`workcell.tasks`)."""

    @property
    def task_name(self) -> str:
        """The name of the task whose scene this is."""
        ...

    def build(self, spec: mujoco.MjSpec, config: WorldConfig) -> None:
        """Add the task's elements to the world's model before it is compiled."""

    def reset(self, world: World, rng: np.random.Generator) -> None:
        """Set the task's part of a trial's start (``rng``: the trial's own stream)."""

    def watch(self, world: World, t: float) -> list[WorldEvent]:
        """What happened to the task's objects in the last control period, after the grasp
        was updated (the world's clock ``t``)."""
        ...


class World:
    """One MuJoCo model and data with the task-level machinery around them; ``scene`` is
    the task's (None: the bare factory, whose boxes no task wants anywhere)."""

    def __init__(self, config: WorldConfig, scene: TaskScene | None = None) -> None:
        self.config = config
        self.scene = scene
        self.model = build_world_model(config, scene)
        self.data = mujoco.MjData(self.model)
        self.boxes = BoxPool(self.model, config)
        self.grasp = Grasp(self.model, self.boxes, config.grasp)
        self.zone = TargetZone(config)
        self.conditions = TrialConditions.nominal(config)
        """The conditions of the current trial (see :mod:`workcell.sim.trial_conditions`)."""
        self.substeps = config.control_substeps
        self.control_dt = self.substeps * config.timestep
        joint = self.model.joint
        self._base_qpos = np.array([self.model.jnt_qposadr[joint(n).id] for n in BASE_JOINTS])
        self._base_dof = np.array([self.model.jnt_dofadr[joint(n).id] for n in BASE_JOINTS])
        self._joint_qpos = np.array([self.model.jnt_qposadr[joint(n).id] for n in JOINT_ORDER])
        self._joint_dof = np.array([self.model.jnt_dofadr[joint(n).id] for n in JOINT_ORDER])
        actuator = self.model.actuator
        self.base_ctrl = np.array([actuator(n).id for n in BASE_JOINTS])
        self.joint_ctrl = np.array([actuator(n).id for n in JOINT_ORDER])
        self.finger_ctrl = {s: np.array([actuator(n).id for n in FINGER_JOINTS[s]]) for s in SIDES}
        self._finger_qpos = {
            s: np.array([self.model.jnt_qposadr[joint(n).id] for n in FINGER_JOINTS[s]])
            for s in SIDES
        }
        self._finger_open = float(self.model.jnt_range[joint(FINGER_JOINTS["l"][0]).id][1])
        self._next_release = 0.0
        self.physics_steps = 0
        """Physics steps since the last reset: the exact sim clock (steps x timestep)."""
        self.sampler: Sampler | None = None
        self._rng = np.random.default_rng(0)
        self._floor_since: dict[int, float] = {}

    # --- lifecycle -------------------------------------------------------------------------

    def reset(
        self,
        joints: NDArray[np.float64],
        seed: int = 0,
        conditions: TrialConditions | None = None,
        task_rng: np.random.Generator | None = None,
    ) -> None:
        """Start state under ``conditions`` (default: the configured ones): the robot at
        the start pose with ``joints`` (JOINT_ORDER), boxes parked, the task's scene set
        from ``task_rng`` (default: a stream of ``seed``'s own).

        ``seed`` fixes everything random that follows (where boxes land on the belt)."""
        if conditions is not None and conditions != self.conditions:
            apply_conditions(self.model, self.data, self.boxes, conditions)
            self.conditions = conditions
            self.boxes.set_box_size(conditions.box_size)
            self.zone.place(conditions.target_center, conditions.box_size[2])
        base_pose = self.conditions.start_pose
        mujoco.mj_resetData(self.model, self.data)
        self.physics_steps = 0
        self._rng = np.random.default_rng(seed)
        self.data.qpos[self._base_qpos] = base_pose
        self.data.qpos[self._joint_qpos] = joints
        self.data.ctrl[self.base_ctrl] = base_pose
        self.data.ctrl[self.joint_ctrl] = joints
        for side in SIDES:
            self.data.qpos[self._finger_qpos[side]] = self._finger_open
            self.data.ctrl[self.finger_ctrl[side]] = self._finger_open
        self.boxes.park_all(self.data)
        self.grasp.reset(self.data)
        self._next_release = self.config.feeder.first_release_s
        self._floor_since.clear()
        if self.scene is not None:
            rng = task_rng if task_rng is not None else np.random.default_rng([seed, 1])
            self.scene.reset(self, rng)
        mujoco.mj_forward(self.model, self.data)

    def hold_feeder(self) -> None:
        """Release no box until the next reset: for a task whose box starts elsewhere than
        on the belt (its scene's reset calls this; the reset after re-arms the feeder)."""
        self._next_release = math.inf

    def step(self, close_l: float, close_r: float) -> list[WorldEvent]:
        """Advance one control period (ctrl already written); returns what happened.

        A :attr:`sampler` is called at exactly its due physics steps, even mid-period; a
        sample due at the period's end is taken after the task state is updated."""
        end = self.physics_steps + self.substeps
        sampler = self.sampler
        while self.physics_steps < end:
            stop = end
            if sampler is not None and self.physics_steps < sampler.next_step < end:
                stop = sampler.next_step
            mujoco.mj_step(self.model, self.data, nstep=stop - self.physics_steps)
            self.physics_steps = stop
            if sampler is not None and stop < end and stop == sampler.next_step:
                sampler.sample()
        if not np.isfinite(self.data.qacc).all():
            raise SimulationError(
                f"physics diverged at t={self.data.time:.3f} s (non-finite accelerations); "
                "lower the timestep or the box mass"
            )
        events = self._update_task(close_l, close_r)
        if sampler is not None and sampler.next_step == end:
            sampler.sample()
        return events

    def _update_task(self, close_l: float, close_r: float) -> list[WorldEvent]:
        t = self.time
        events: list[WorldEvent] = []
        changed = self.grasp.update(self.data, close_l, close_r)
        if changed is not None:
            events.append(GraspChanged(t, changed[0].index, changed[1]))
        if self.scene is not None:
            events += self.scene.watch(self, t)
        for slot in self.boxes.slots:
            if slot.state is BoxState.ACTIVE:
                self._clear_if_on_floor(slot, t)
        if t + 1e-6 >= self._next_release and self.boxes.feed_clear(self.data):
            feeder = self.config.feeder
            lateral = float(self._rng.uniform(-feeder.lateral_jitter, feeder.lateral_jitter))
            yaw = float(self._rng.uniform(-feeder.yaw_jitter, feeder.yaw_jitter))
            released = self.boxes.release(self.data, t, lateral, yaw)
            if released is not None:
                events.append(BoxReleased(t, released.index))
                # Keep to the schedule; a release held back by a blocked feed point does
                # not shift the ones after it.
                while self._next_release <= t + 1e-6:
                    self._next_release += self.conditions.release_interval_s
        return events

    def _clear_if_on_floor(self, slot: BoxSlot, t: float) -> None:
        on_floor = self.boxes.position(self.data, slot)[2] < self.conditions.box_size[2]
        if not on_floor:
            self._floor_since.pop(slot.index, None)
            return
        since = self._floor_since.setdefault(slot.index, t)
        if t - since >= FLOOR_CLEAR_S:
            self.boxes.park(self.data, slot)
            del self._floor_since[slot.index]

    # --- state -----------------------------------------------------------------------------

    @property
    def time(self) -> float:
        return float(self.data.time)

    @property
    def base_pose(self) -> NDArray[np.float64]:
        """(x, y, yaw) of the base in the world."""
        pose: NDArray[np.float64] = self.data.qpos[self._base_qpos]  # an array index copies
        return pose

    @property
    def base_velocity(self) -> NDArray[np.float64]:
        """(vx, vy, wz) of the base in the world frame."""
        velocity: NDArray[np.float64] = self.data.qvel[self._base_dof]  # a copy
        return velocity

    @property
    def joint_positions(self) -> NDArray[np.float64]:
        joints: NDArray[np.float64] = self.data.qpos[self._joint_qpos]  # a copy
        return joints

    @property
    def joint_velocities(self) -> NDArray[np.float64]:
        return np.array(self.data.qvel[self._joint_dof])

    def gripper_opening(self, side: str) -> float:
        """Finger opening, 0 closed .. 1 fully open."""
        a, b = self._finger_qpos[side]
        qpos = self.data.qpos
        return float(qpos[a] + qpos[b]) / (2.0 * self._finger_open)

    def set_gripper(self, side: str, close: float) -> None:
        self.data.ctrl[self.finger_ctrl[side]] = self._finger_open * (1.0 - close)

    def tcp_pose(self, side: str) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """World position and quaternion (w, x, y, z) of one TCP."""
        site = self.data.site(f"tcp_{side}")
        quat = np.zeros(4)
        mujoco.mju_mat2Quat(quat, site.xmat)
        return np.array(site.xpos), quat

    def to_base_frame(self, position: NDArray[np.float64]) -> NDArray[np.float64]:
        """A world point expressed in the base frame (origin on the floor under the base)."""
        x, y, yaw = self.base_pose
        c, s = math.cos(yaw), math.sin(yaw)
        dx, dy = position[0] - x, position[1] - y
        return np.array([c * dx + s * dy, -s * dx + c * dy, position[2]])

    def to_world_frame(self, position: NDArray[np.float64]) -> NDArray[np.float64]:
        x, y, yaw = self.base_pose
        c, s = math.cos(yaw), math.sin(yaw)
        return np.array(
            [
                x + c * position[0] - s * position[1],
                y + s * position[0] + c * position[1],
                position[2],
            ]
        )

    def check_finite(self) -> None:
        if not np.isfinite(self.data.qpos).all():
            raise SimulationError(f"non-finite state at t={self.time:.3f} s")

"""Differential inverse kinematics for both arms and the spine, solved with mink.

The solver runs on the robot-only model (fixed base at the origin), so targets are base-frame
TCP poses. Two frame tasks (one per TCP), a posture task, joint position and velocity limits,
and collision avoidance between the arms and between each arm and a proxy of the fixture
they keep clear of (a mocap box placed where that fixture is, seen from the base).
"""

from __future__ import annotations

from collections.abc import Sequence
from ctypes import c_int

import daqp
import mink
import numpy as np
from numpy.typing import NDArray

from workcell.control.collision_limit import StepCollisionLimit
from workcell.control.ik_limits import FixedRowsConfigurationLimit, FixedVelocityLimit
from workcell.control.ik_residual import residuals
from workcell.sim import panda
from workcell.sim.config import WorldConfig
from workcell.sim.joints import JOINT_ORDER, SIDES, SPINE_JOINT, arm_joint_names
from workcell.sim.scene import OBSTACLE_PROXY, OBSTACLE_PROXY_GEOM, build_ik_model

HOME_ARM: tuple[float, ...] = (0.0, 0.2, 0.0, -1.9, 0.0, 2.1, 0.785)
"""A relaxed arm posture with the hand in front of the shoulder."""
HOME_ARM_RIGHT: tuple[float, ...] = HOME_ARM
ARM_DETECTION_DISTANCE = 0.2
"""How close (m) two geoms of different arms get before the IK limits their approach."""


def arm_geoms(side: str) -> list[str]:
    return [*(f"arm_{side}_geom{i}" for i in range(2, 8)), f"hand_{side}_housing", f"pad_{side}"]


class BimanualIK:
    """Keeps an IK configuration and moves it toward the TCP targets each control step."""

    def __init__(self, config: WorldConfig, home_spine: float) -> None:
        self.model = build_ik_model(config)
        self.configuration = mink.Configuration(self.model)
        self.frame_tasks = {
            side: mink.FrameTask(
                frame_name=f"tcp_{side}",
                frame_type="site",
                position_cost=1.0,
                orientation_cost=0.3,
                lm_damping=1e-3,
            )
            for side in SIDES
        }
        posture_cost = np.full(self.model.nv, 1e-2)
        posture_cost[self._dof(SPINE_JOINT)] = 0.05
        self.posture = mink.PostureTask(self.model, cost=posture_cost)
        velocities: dict[str, float] = {SPINE_JOINT: 0.3}
        for side in SIDES:
            for name, vmax in zip(arm_joint_names(side), panda.VELOCITY_LIMITS, strict=True):
                velocities[name] = vmax
        proxy_geom = OBSTACLE_PROXY_GEOM
        self.limits: list[mink.Limit] = [
            FixedRowsConfigurationLimit(self.model),
            FixedVelocityLimit(self.model, velocities),
            StepCollisionLimit(
                self.model,
                geom_pairs=[([*arm_geoms("l"), *arm_geoms("r")], [proxy_geom])],
                minimum_distance_from_collisions=0.015,
                collision_detection_distance=0.08,
            ),
            # The hands can close on each other at up to ~6 m/s together (both arms at
            # their joint speed limits), 15 cm in one 25 ms period: the arm-arm limit must
            # see them coming from farther than that.
            StepCollisionLimit(
                self.model,
                geom_pairs=[(arm_geoms("l"), arm_geoms("r"))],
                gate=False,  # the shoulders' bounding spheres always overlap
                minimum_distance_from_collisions=0.015,
                collision_detection_distance=ARM_DETECTION_DISTANCE,
            ),
        ]
        self._qadr = np.array(
            [self.model.jnt_qposadr[self.model.joint(name).id] for name in JOINT_ORDER]
        )
        self._proxy = self.model.body(OBSTACLE_PROXY).mocapid[0]
        self.tcp_sites = {side: self.model.site(f"tcp_{side}").id for side in SIDES}
        """Each TCP's site id in the IK model (``configuration.data.site_xpos`` rows)."""
        self.target_positions = np.zeros((len(SIDES), 3))
        """Each TCP's target position (rows in SIDES order), kept with the frame tasks."""
        self._target_asked: dict[str, tuple[tuple[float, ...], tuple[float, ...]] | None] = (
            dict.fromkeys(SIDES)
        )
        """The (position, quaternion) each frame task's target was last set from, if set
        by :meth:`set_target` (an operator holds a target still most of the time)."""
        self._open_rows: dict[int, tuple[NDArray[np.float64], NDArray[np.intc]]] = {}
        self.solves = 0
        """IK solves so far (diagnostics: how often the QP ran)."""
        self.home = np.zeros(len(JOINT_ORDER))
        self.home[0] = home_spine
        self.home[3:10] = HOME_ARM
        self.home[10:17] = _mirror(HOME_ARM)
        self.reset(self.home)

    def _dof(self, joint: str) -> int:
        return int(self.model.jnt_dofadr[self.model.joint(joint).id])

    def reset(self, joints: NDArray[np.float64]) -> None:
        """Put the IK configuration at ``joints`` (17, in JOINT_ORDER) and hold there."""
        q = self.configuration.data.qpos.copy()
        q[self._qadr] = joints
        self.configuration.update(q)
        self.posture.set_target(q)
        for side in SIDES:
            self.hold(side)

    @property
    def joints(self) -> NDArray[np.float64]:
        """The IK solution in JOINT_ORDER."""
        return np.array(self.configuration.q[self._qadr])

    def place_obstacle(
        self, position: NDArray[np.float64] | Sequence[float], quaternion: Sequence[float]
    ) -> None:
        """Put the obstacle proxy at its pose in the base frame."""
        self.configuration.data.mocap_pos[self._proxy] = position
        self.configuration.data.mocap_quat[self._proxy] = quaternion

    def tcp_pose(self, side: str) -> mink.SE3:
        return self.configuration.get_transform_frame_to_world(f"tcp_{side}", "site")

    def hold(self, side: str) -> None:
        """Make the arm's current pose its target."""
        task = self.frame_tasks[side]
        task.set_target_from_configuration(self.configuration)
        self._target_asked[side] = None
        assert task.transform_target_to_world is not None
        self.target_positions[SIDES.index(side)] = task.transform_target_to_world.translation()

    def set_target(self, side: str, position: Sequence[float], quaternion: Sequence[float]) -> None:
        asked = (tuple(position), tuple(quaternion))
        if asked == self._target_asked[side]:
            return  # the target already set: the same pose again
        self._target_asked[side] = asked
        wxyz = np.asarray(quaternion, dtype=float)
        translation = np.asarray(position, dtype=float)
        pose = mink.SE3.from_rotation_and_translation(
            mink.SO3(wxyz / np.linalg.norm(wxyz)), translation
        )
        self.frame_tasks[side].set_target(pose)
        self.target_positions[SIDES.index(side)] = translation

    def step(self, dt: float) -> NDArray[np.float64]:
        """One differential IK step of length ``dt``; returns the joints (JOINT_ORDER)."""
        return self.advance(self.solve(dt), dt)

    def solve(self, horizon: float) -> NDArray[np.float64]:
        """The joint velocity that moves toward the targets over ``horizon`` seconds, within
        the joint, velocity and collision limits for that long."""
        tasks = [*self.frame_tasks.values(), self.posture]
        self.solves += 1
        # mink.solve_ik's steps without its check of the configuration against the joint
        # limits, which only logs (the configuration limit keeps every step inside them),
        # and daqp called as qpsolvers calls it, less the rows that bound nothing: a
        # collision pair beyond its detection distance is a zero row with an infinite
        # bound, which never becomes active (the solution is the same, bit for bit).
        problem = mink.build_ik(self.configuration, tasks, horizon, 1e-3, self.limits)
        assert problem.G is not None and problem.h is not None
        bounding = np.isfinite(problem.h)
        rows, upper = problem.G[bounding], problem.h[bounding]
        lower, sense = self._open_below(upper.size)
        x, _, exitflag, _ = daqp.solve(problem.P, problem.q, rows, upper, lower, sense)
        if exitflag <= 0:
            raise mink.NoSolutionFound("daqp")
        velocity: NDArray[np.float64] = x / horizon
        return velocity

    def _open_below(self, rows: int) -> tuple[NDArray[np.float64], NDArray[np.intc]]:
        """daqp's lower bounds (none: -1e30, as qpsolvers passes) and constraint senses
        (0: inequality) for ``rows`` inequality rows, built once per row count (a handful
        of counts recur, as collision pairs come within reach and leave)."""
        built = self._open_rows.get(rows)
        if built is None:
            built = (np.full(rows, -1e30), np.zeros(rows, dtype=c_int))
            self._open_rows[rows] = built
        return built

    def advance(self, velocity: NDArray[np.float64], dt: float) -> NDArray[np.float64]:
        """Move the configuration at ``velocity`` for ``dt``; returns the joints."""
        self.configuration.integrate_inplace(velocity, dt)
        return self.joints

    def residual(self, side: str) -> float:
        """Position error of one TCP from its target, metres (as :func:`residuals`)."""
        here = self.configuration.data.site_xpos[self.tcp_sites[side]]
        target = self.target_positions[SIDES.index(side)]
        return float(residuals(here[np.newaxis], target[np.newaxis])[0])


def _mirror(arm: Sequence[float]) -> tuple[float, ...]:
    """The right arm's posture mirroring a left-arm posture through the sagittal plane."""
    q = list(arm)
    for i in (0, 2, 4):
        q[i] = -q[i]
    q[6] = -q[6] + 1.5708
    return tuple(q)

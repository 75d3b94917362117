"""Turns a :class:`Command` into actuator controls: base motion, IK, grippers and head."""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from workcell.control.base_motion import BaseMotion
from workcell.control.command import Command
from workcell.control.ik import BimanualIK
from workcell.sim.joints import HEAD_JOINTS, JOINT_ORDER, SIDES
from workcell.sim.world import World

MAX_BASE_LEAD = 0.15
"""How far (m, rad) the base reference may run ahead of the measured base pose."""

_HEAD = [JOINT_ORDER.index(n) for n in HEAD_JOINTS]


class RobotController:
    def __init__(self, world: World) -> None:
        self.world = world
        self.solve_held_arms = True
        """Solve the IK also while neither arm follows its target (both held). A person's
        session (:class:`~workcell.recording.drivers.TeleopDriver`) turns it off: a held
        arm's target is where the IK configuration already is, so the solve would only
        drift the arms toward the posture task; skipped, the configuration stays as it
        is and the first period an arm follows again solves at once. The expert and the
        policies keep it on (their record is what it was)."""
        self._skipped = False
        """The IK has not solved since the configuration was last brought up to date
        (periods skipped while both arms were held)."""
        self.base = BaseMotion(world.config.robot)
        self.ik = BimanualIK(world.config, home_spine=world.config.robot.start_spine)
        self._following = dict.fromkeys(SIDES, False)
        self._ik_every = world.config.robot.ik_every
        self._ik_phase = 0
        """Control periods since the last IK solve (0: solve in this one)."""
        self._ik_velocity = np.zeros(self.ik.model.nv)
        self._obstacle_center = np.array(world.config.arm_obstacle[0])
        model = world.model
        self._head_range = np.array([model.jnt_range[model.joint(n).id] for n in HEAD_JOINTS])

    @property
    def home_joints(self) -> NDArray[np.float64]:
        return self.ik.home.copy()

    def reset(self, base_pose: tuple[float, float, float], joints: NDArray[np.float64]) -> None:
        self.base.reset(base_pose)
        self.ik.reset(joints)
        self._following = dict.fromkeys(SIDES, False)
        self._ik_phase = 0
        self._skipped = False

    def apply(self, command: Command) -> None:
        """Write the controls for one control period."""
        world, dt = self.world, self.world.control_dt
        pose = world.base_pose
        self.base.limit_lead(pose, MAX_BASE_LEAD)
        world.data.ctrl[world.base_ctrl] = self.base.step(command.executed_base, dt)
        yaw = float(pose[2])
        self.ik.place_obstacle(
            world.to_base_frame(self._obstacle_center),
            (math.cos(-yaw / 2), 0.0, 0.0, math.sin(-yaw / 2)),
        )
        for side, arm in (("l", command.left), ("r", command.right)):
            if arm.follow:
                self.ik.set_target(side, arm.position, arm.quaternion)
            elif self._following[side]:
                self.ik.hold(side)
            self._following[side] = arm.follow
        if not (self.solve_held_arms or command.left.follow or command.right.follow):
            joints = self._hold_still()
        else:
            if self._skipped:  # the obstacle proxy moved meanwhile: the kinematics first
                self.ik.configuration.update()
                self._skipped = False
            if self._ik_phase == 0:  # solve for the periods until the next solve
                self._ik_velocity = self.ik.solve(self._ik_every * dt)
            self._ik_phase = (self._ik_phase + 1) % self._ik_every
            joints = self.ik.advance(self._ik_velocity, dt)
        joints[_HEAD] = np.clip(command.head, self._head_range[:, 0], self._head_range[:, 1])
        world.data.ctrl[world.joint_ctrl] = joints
        world.set_gripper("l", command.close_left)
        world.set_gripper("r", command.close_right)

    def _hold_still(self) -> NDArray[np.float64]:
        """Both arms held and :attr:`solve_held_arms` off: no solve, the IK configuration
        stays where it is, and the next period an arm follows solves first."""
        self._skipped = True
        self._ik_phase = 0
        self._ik_velocity[:] = 0.0
        return self.ik.joints

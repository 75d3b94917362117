"""What the simulation thread sends after a control step: State, HUD and task events."""

from __future__ import annotations

import dataclasses
import math

import mujoco
import numpy as np

from workcell.control.command import ArmCommand
from workcell.intervene.operator import InterveningOperator
from workcell.protocol.messages import State
from workcell.protocol.scene import Pose
from workcell.server.scene import DIGITS, PoseReader
from workcell.sim.joints import SIDES
from workcell.sim.world import World
from workcell.task import events as ev
from workcell.task.hud import Hud
from workcell.task.runner import SessionRunner
from workcell.teleop.operator import TeleopOperator
from workcell.teleop.rotation import multiply


def hud_message(hud: Hud) -> Hud:
    """The HUD as sent: its clocks to the millisecond."""
    return dataclasses.replace(
        hud, countdown_s=round(hud.countdown_s, 3), remaining_s=round(hud.remaining_s, 3)
    )


def event_message(event: ev.TaskEvent) -> ev.TaskEvent:
    """A task event as sent: its time to the microsecond."""
    return dataclasses.replace(event, t_sim=round(event.t_sim, 6))


def _world_pose(world: World, base_pose: Pose) -> Pose:
    """A base-frame pose in the world frame."""
    x, y, z = (round(float(v), DIGITS) for v in world.to_world_frame(np.array(base_pose[:3])))
    yaw = float(world.base_pose[2])
    heading = (math.cos(yaw / 2), 0.0, 0.0, math.sin(yaw / 2))
    w, qx, qy, qz = (round(v, DIGITS) for v in multiply(heading, base_pose[3:]))
    return (x, y, z, w, qx, qy, qz)


class StateBuilder:
    """Builds :class:`State` messages for one running session."""

    def __init__(
        self,
        runner: SessionRunner,
        operator: TeleopOperator,
        intervening: InterveningOperator[TeleopOperator] | None = None,
    ) -> None:
        self.runner = runner
        self.operator = operator
        self.intervening = intervening
        """The session's operator when an autonomous driver drives it (the HUD says who
        drives now)."""
        model = runner.sim.world.model
        self.reader = PoseReader(model)
        self.seq = 0
        self._tcp_sites = {side: model.site(f"tcp_{side}").id for side in SIDES}
        self._quat = np.zeros(4)

    def _target(self, side: str, arm: ArmCommand) -> Pose:
        """The arm's TCP target in the world: the one it follows, else where it is (the
        measured TCP, read in the world frame at once)."""
        world = self.runner.sim.world
        if arm.follow:
            return _world_pose(world, (*arm.position, *arm.quaternion))
        site = self._tcp_sites[side]
        mujoco.mju_mat2Quat(self._quat, world.data.site_xmat[site])
        x, y, z = (round(v, DIGITS) for v in world.data.site_xpos[site].tolist())
        w, qx, qy, qz = (round(v, DIGITS) for v in self._quat.tolist())
        return (x, y, z, w, qx, qy, qz)

    def _hud(self) -> Hud:
        hud = self.runner.hud()
        intervening = self.intervening
        if intervening is None:
            return hud
        return dataclasses.replace(
            hud, driver=intervening.driver_name, taken_over=intervening.person_drives
        )

    def build(self) -> State:
        runner = self.runner
        world = runner.sim.world
        command = runner.last_command
        self.seq += 1
        return State(
            seq=self.seq,
            t_sim=round(runner.trial_time, 6),
            poses=self.reader.poses(world.data),
            hud=hud_message(self._hud()),
            input_seq=self.operator.applied_seq,
            tcp_targets=(self._target("l", command.left), self._target("r", command.right)),
            following=(command.left.follow, command.right.follow),
        )

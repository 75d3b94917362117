"""The controlled robot in its world: the loop every operator drives, one command per step."""

from __future__ import annotations

from workcell.control.command import Command
from workcell.control.controller import RobotController
from workcell.sim.config import WorldConfig
from workcell.sim.events import WorldEvent
from workcell.sim.world import World


class Simulation:
    """Physics, control, grasping and the feeder, advanced one control period per command."""

    def __init__(self, config: WorldConfig) -> None:
        self.config = config
        self.world = World(config)
        self.controller = RobotController(self.world)
        self.reset()

    def reset(self, seed: int = 0, base_pose: tuple[float, float, float] | None = None) -> None:
        """Back to the start state; the same ``seed`` gives the same trial start and feed."""
        pose = base_pose if base_pose is not None else self.config.robot.start_pose
        joints = self.controller.home_joints
        self.world.reset(pose, joints, seed)
        self.controller.reset(pose, joints)

    @property
    def time(self) -> float:
        return self.world.time

    @property
    def control_dt(self) -> float:
        return self.world.control_dt

    def step(self, command: Command) -> list[WorldEvent]:
        """Apply ``command`` for one control period and return the world's events."""
        self.controller.apply(command)
        return self.world.step(command.gripper_left, command.gripper_right)

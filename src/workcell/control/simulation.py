"""The controlled robot in its world: the loop every operator drives, one command per step."""

from __future__ import annotations

from workcell.control.command import Command
from workcell.control.controller import RobotController
from workcell.sim.config import WorldConfig
from workcell.sim.events import WorldEvent
from workcell.sim.trial_conditions import TrialConditions
from workcell.sim.trial_start import start_trial
from workcell.sim.world import TaskScene, World


class Simulation:
    """Physics, control, grasping, the feeder and the task's scene (``scene``; None: the
    bare factory), advanced one control period per command."""

    def __init__(self, config: WorldConfig, scene: TaskScene | None = None) -> None:
        self.config = config
        self.world = World(config, scene)
        self.controller = RobotController(self.world)
        self.reset()

    def reset(self, seed: int = 0) -> TrialConditions:
        """Back to the start state; the same ``seed`` gives the same trial conditions, start
        and feed. Returns the trial's conditions (drawn when randomization is on), with
        what the task's scene drew for the trial (:meth:`TrialConditions.with_task`)."""
        joints = self.controller.home_joints
        conditions = start_trial(self.world, joints, seed)
        self.controller.reset(conditions.start_pose, joints)
        return conditions

    @property
    def time(self) -> float:
        return self.world.time

    @property
    def control_dt(self) -> float:
        return self.world.control_dt

    def step(self, command: Command) -> list[WorldEvent]:
        """Apply ``command`` for one control period and return the world's events."""
        self.controller.apply(command)
        return self.world.step(command.close_left, command.close_right)

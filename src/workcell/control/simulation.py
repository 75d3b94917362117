"""The controlled robot in its world: the loop every operator drives, one command per step."""

from __future__ import annotations

import numpy as np

from workcell.control.command import Command
from workcell.control.controller import RobotController
from workcell.sim.config import WorldConfig
from workcell.sim.events import WorldEvent
from workcell.sim.trial_conditions import TrialConditions
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
        draw_stream, feed_stream, task_stream = np.random.SeedSequence(seed).spawn(3)
        conditions = TrialConditions.draw(self.config, np.random.default_rng(draw_stream))
        joints = self.controller.home_joints
        feed_seed = int(feed_stream.generate_state(1)[0])
        task_rng = np.random.default_rng(task_stream)
        self.world.reset(joints, feed_seed, conditions, task_rng)
        self.controller.reset(conditions.start_pose, joints)
        return self.world.conditions  # with what the task's scene drew, if anything

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

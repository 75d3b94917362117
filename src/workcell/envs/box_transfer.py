"""``workcell/BoxTransfer-v0``: carry boxes from the conveyor to the delivery table.

One step is one recorded frame period (1/20 s of sim time by default: several control
steps), driven by the :class:`Command` the action vector stands for, the only way to move
the robot. An episode is one trial of the session runner (:class:`SessionRunner`, the one
episode loop of every operator), which the task judges. ``reset(seed=s)`` is the
deterministic world reset of a recorded trial whose ``trial_seed`` is ``s`` (followed by
the same idle countdown), so replaying that trial's exported actions from
``reset(seed=trial_seed)`` retraces it. Observations are those of
:mod:`workcell.envs.observation` (LeRobot's gym convention). Rewards and ends follow the
export (:mod:`workcell.export.episode_data`): 1.0 per box delivered in the step (or, with
``BoxTransferConfig(reward="staged")``, each of the task's stages reached earns its share,
from the same judge whose stage ``info["stage"]`` names and the audit reads back);
terminated once the task judges the episode a success (``info["is_success"]``: its
``required_boxes`` delivered), truncated at the time limit.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import gymnasium
import numpy as np
from gymnasium import spaces
from numpy.typing import NDArray

from workcell.control.command import Command
from workcell.control.simulation import Simulation
from workcell.envs.actions import command_from_action
from workcell.envs.config import BoxTransferConfig
from workcell.envs.observation import Observation, ObservationBuilder
from workcell.envs.spaces import action_space, observation_space
from workcell.errors import ConfigError
from workcell.render.renderer import OffscreenRenderer
from workcell.sim.world import World
from workcell.task.hud import HudPhase
from workcell.task.runner import SessionRunner
from workcell.task.schedule import TrialSpec
from workcell.tasks import WorldName
from workcell.tasks.registry import load_task

MAX_SEED = 2**63 - 1


class _Actions:
    """The operator of an episode: the command of the latest action, every control period."""

    def __init__(self) -> None:
        self.command = Command()

    def start_trial(self, trial_seed: int) -> None:
        self.command = Command()

    def act(self, world: World) -> Command:
        return self.command


class BoxTransferEnv(gymnasium.Env[dict[str, Any], NDArray[Any]]):
    metadata: dict[str, Any] = {"render_modes": ["rgb_array"], "render_fps": 20}  # noqa: RUF012
    observation_space: spaces.Dict
    action_space: spaces.Box

    def __init__(
        self,
        config: BoxTransferConfig | None = None,
        render_mode: str | None = None,
        session_parameters: Mapping[str, Any] | None = None,
        world: WorldName | None = None,
        task: str | None = None,
    ) -> None:
        """``config``, or the ``session_parameters`` a store recorded (as in the HDF5
        export's ``env_args``), or the defaults; ``world`` (``D0``, ``D1``, ``D2``) sets
        the randomization ranges to the task's world of that name; ``task`` (a ``task.kind``)
        replaces the configuration's task (each built-in task's registered id passes its
        own)."""
        if config is None:
            config = (
                BoxTransferConfig()
                if session_parameters is None
                else BoxTransferConfig.from_parameters(session_parameters)
            )
        if task is not None:
            config = config.for_task(task)
        self.task = load_task(config.session.task.kind)
        if world is not None:
            config = config.in_world(self.task, world)
        if render_mode not in (None, *self.metadata["render_modes"]):
            raise ConfigError([f"render_mode {render_mode!r}: must be None or 'rgb_array'"])
        self.config = config
        self.render_mode = render_mode
        self.metadata = {**self.metadata, "render_fps": config.fps}
        self.sim = Simulation(config.session.world, self.task.scene())
        self._observations = ObservationBuilder(
            self.sim, self.task, config.cameras, config.camera_size
        )
        self.observation_space = observation_space(config)
        self.action_space = action_space(config, self.sim.world)
        self._renderer: OffscreenRenderer | None = None
        self._actions = _Actions()
        self._runner = SessionRunner(config.episode_session, self.sim, self._actions, max_trials=1)
        self._episode = TrialSpec(0, "practice", None, None, config.required_boxes, config.limit_s)
        self._frames = 0
        self._world_seed = 0

    # --- gymnasium API --------------------------------------------------------------------

    def reset(
        self, *, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[Observation, dict[str, Any]]:
        super().reset(seed=seed)
        world_seed = seed if seed is not None else int(self.np_random.integers(MAX_SEED))
        self._world_seed = world_seed
        config = self.config
        self._runner = SessionRunner(config.episode_session, self.sim, self._actions, max_trials=1)
        self._runner.start(self._episode, world_seed)
        while self._runner.phase is HudPhase.COUNTDOWN:  # idle, as before a recorded trial
            self._runner.step()
        self._frames = 0
        self._observations.restart()
        return self._observations.observe(self._actions.command), self._info()

    def step(self, action: NDArray[Any]) -> tuple[Observation, float, bool, bool, dict[str, Any]]:
        space = self.action_space
        clipped = np.clip(np.asarray(action, dtype=np.float64), space.low, space.high)
        self._actions.command = command_from_action(clipped)
        runner = self._runner
        done, stage = runner.judge.done, self._stage_index()
        for _ in range(self.config.control_steps_per_frame):
            runner.step()
        self._frames += 1
        if self.config.reward == "staged":
            reward = (self._stage_index() - stage) / (len(self.task.stages) - 1)
        else:
            reward = float(runner.judge.done - done)
        outcome = runner.results[-1].outcome if runner.results else None
        observation = self._observations.observe(self._actions.command)
        terminated = outcome in ("success", "failed")  # the task ended it: success or failure
        return observation, reward, terminated, outcome == "timeout", self._info()

    def render(self) -> NDArray[np.uint8] | None:
        if self.render_mode != "rgb_array":
            return None
        if self._renderer is None:
            size = self.config.render_size
            self._renderer = OffscreenRenderer(self.sim.world.model, size.width, size.height)
        return self._renderer.render(self.sim.world.data, self.config.render_camera)

    def close(self) -> None:
        self._observations.close()
        if self._renderer is not None:
            self._renderer.close()
            self._renderer = None

    # --- state ----------------------------------------------------------------------------

    @property
    def t_sim(self) -> float:
        """Seconds since the episode started (the trial clock)."""
        return self._frames / self.config.fps

    @property
    def is_success(self) -> bool:
        """The task judged the episode a success (its boxes delivered)."""
        results = self._runner.results
        return bool(results) and results[-1].outcome == "success"

    @property
    def _max_episode_steps(self) -> int:
        """The episode's step limit, where LeRobot's rollout looks for it (the task's least
        time limit raises the configured one: :attr:`Task.least_time_limit_s`)."""
        least = math.ceil(self.task.least_time_limit_s * self.config.fps)
        return max(self.config.max_episode_steps, least)

    def _stage_index(self) -> int:
        return self.task.stages.index(self._runner.stage)

    def _info(self) -> dict[str, Any]:
        return {
            "t_sim": self.t_sim,
            "boxes_delivered": self._runner.judge.done,
            "stage": self._runner.stage,
            "is_success": self.is_success,
            "world_seed": self._world_seed,
        }

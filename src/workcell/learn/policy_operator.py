"""A learned policy as an operator: observe at each frame instant, act through ``Command``.

The policy sees what a policy trained on a Workcell export was trained on: the
observation of :mod:`workcell.envs.observation`, turned into the export's features by
LeRobot's own ``preprocess_observation`` and the policy's saved pre-processor
(normalisation), exactly as ``lerobot-eval`` does for a Gymnasium environment. It decides
once per recorded frame (the dataset's rate) and its action holds for that frame's
control periods, as in :class:`workcell.envs.box_transfer.BoxTransferEnv`; the action is
clipped to the environment's action space and becomes a :class:`Command`, the path every
operator drives. So a session run by a policy is recorded and audited like any other.
"""

from __future__ import annotations

import contextlib
import io
from collections.abc import Iterator
from typing import Any

import numpy as np

from workcell.control.command import Command
from workcell.control.simulation import Simulation
from workcell.envs.actions import command_from_action
from workcell.envs.config import BoxTransferConfig
from workcell.envs.observation import ENVIRONMENT_STATE, ObservationBuilder
from workcell.envs.spaces import action_space
from workcell.export.boxes import environment_names, world_environment_names
from workcell.export.options import ImageSize
from workcell.learn.checkpoint import PolicyCheckpoint
from workcell.learn.errors import LearnError, MissingLearnExtraError
from workcell.learn.features import PolicyInputs, policy_inputs
from workcell.session.config import SessionConfig
from workcell.sim.world import World
from workcell.tasks.registry import load_task

INFERENCE_THREADS = 1
"""Torch threads for inference. A policy decides at most once per frame (20 Hz), so more
threads buy little, while idle OpenMP threads spin on the core the store's writer process
uses."""


class PolicyOperator:
    """Drives with the policy at ``checkpoint`` (see :meth:`PolicyCheckpoint.locate`)."""

    def __init__(
        self,
        checkpoint: PolicyCheckpoint,
        config: SessionConfig,
        sim: Simulation,
        device: str | None = None,
        threads: int = INFERENCE_THREADS,
        *,
        verbose: bool = False,
    ) -> None:
        """``verbose``: let torch and LeRobot print what they print while the policy loads
        (by default it is dropped: collect's table comes first)."""
        with library_output(verbose):
            torch = _import("torch")
            torch.set_num_threads(threads)
            self.checkpoint = checkpoint
            self.device = device or ("cuda" if torch.cuda.is_available() else "cpu")
            self._torch = torch
            self._policy, self._preprocessor, self._postprocessor = _load(checkpoint, self.device)
        task = load_task(config.task.kind)
        pool = config.world.feeder.pool_size
        self.inputs: PolicyInputs = policy_inputs(
            checkpoint,
            self._policy.config,
            environment_names(pool, task.goal_names),
            world_environment_names(pool, task.goal_names),
        )
        environment = BoxTransferConfig(session=config)  # checks that frames are whole steps
        self.control_steps_per_frame = environment.control_steps_per_frame
        space = action_space(environment, sim.world)
        self._low, self._high = space.low.astype(np.float64), space.high.astype(np.float64)
        size = self.inputs.image_size or ImageSize()
        self._observations = ObservationBuilder(sim, task, self.inputs.cameras, size)
        self._task_def, self._sim = task, sim
        self._task = task.instruction(1)
        """What the current trial asks in words (:meth:`Task.trial_instruction`)."""
        self._command = Command()
        self._steps = 0
        self.decisions = 0
        """Policy calls so far (one per frame)."""

    def start_trial(self, trial_seed: int) -> None:
        self._policy.reset()
        self._observations.restart()
        conditions = self._sim.world.conditions.as_dict()  # the trial's, as recorded
        self._task = self._task_def.trial_instruction(1, conditions)
        self._command = Command()
        self._steps = 0

    def act(self, world: World) -> Command:
        if self._steps % self.control_steps_per_frame == 0:
            self._command = self._decide()
        self._steps += 1
        return self._command

    def resume(self, world: World, command: Command) -> None:
        """Go on from the world as a person who took over left it: the queued actions of a
        chunking policy are dropped and it decides afresh at the next control period,
        ``command`` (the person's last) as the action before."""
        self._policy.reset()
        self._command = command
        self._steps = 0

    def close(self) -> None:
        self._observations.close()

    def _decide(self) -> Command:
        from lerobot.envs.utils import preprocess_observation  # noqa: PLC0415

        observation = self._observations.observe(self._command)
        read = self.inputs.environment_size
        observation[ENVIRONMENT_STATE] = observation[ENVIRONMENT_STATE][:read]
        batch: dict[str, Any] = preprocess_observation(observation)
        batch["task"] = [self._task]
        batch = self._preprocessor(batch)
        with self._torch.inference_mode():
            action = self._policy.select_action(batch)
        action = self._postprocessor(action)
        values = np.asarray(action.to("cpu").numpy(), dtype=np.float64).reshape(-1)
        self.decisions += 1
        if not np.all(np.isfinite(values)):
            raise LearnError(
                f"policy {self.checkpoint.operator_id} returned a non-finite action at decision "
                f"{self.decisions}: {values.tolist()}"
            )
        return command_from_action(np.clip(values, self._low, self._high))


@contextlib.contextmanager
def library_output(verbose: bool) -> Iterator[None]:
    """Within: what libraries print to standard output and error (LeRobot's "Loading
    weights from local directory", Python warnings, log records with no handler of their
    own) is dropped, unless ``verbose``. Errors still raise."""
    if verbose:
        yield
        return
    dropped = io.StringIO()
    with contextlib.redirect_stdout(dropped), contextlib.redirect_stderr(dropped):
        yield


def _import(name: str) -> Any:
    try:
        return __import__(name)
    except ImportError:
        raise MissingLearnExtraError(name) from None


def _load(checkpoint: PolicyCheckpoint, device: str) -> tuple[Any, Any, Any]:
    """The policy (eval mode, on ``device``) and its saved pre- and post-processors."""
    _import("lerobot")
    from lerobot.configs.policies import PreTrainedConfig  # noqa: PLC0415
    from lerobot.policies.factory import get_policy_class, make_pre_post_processors  # noqa: PLC0415

    path = str(checkpoint.path)
    try:
        config = PreTrainedConfig.from_pretrained(path)
        config.device = device
        policy = get_policy_class(config.type).from_pretrained(path, config=config)
        preprocessor, postprocessor = make_pre_post_processors(
            config,
            pretrained_path=path,
            preprocessor_overrides={"device_processor": {"device": device}},
        )
    except (OSError, ValueError, KeyError, NotImplementedError) as error:
        raise LearnError(f"policy {path!r} cannot be loaded by LeRobot: {error}") from None
    policy.to(device)
    policy.eval()
    return policy, preprocessor, postprocessor

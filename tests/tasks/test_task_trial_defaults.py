"""A task's own count of objects and least time limit: a palletize trial asks its four
boxes and gets 180 s whatever the session's schedule says, sort asks four boxes, box
transfer keeps the schedule's (one box, 120 s), in the session runner, the trial's record
and the environment alike."""

from __future__ import annotations

import dataclasses

import gymnasium
import pytest

from workcell.control.command import Command
from workcell.control.simulation import Simulation
from workcell.envs import ENV_IDS
from workcell.envs.box_transfer import BoxTransferEnv
from workcell.session.config import SessionConfig, TaskConfig
from workcell.sim.config import WorldConfig
from workcell.sim.world import World
from workcell.task.runner import SessionRunner
from workcell.tasks.registry import load_task


class _Still:
    def start_trial(self, trial_seed: int) -> None:
        pass

    def act(self, world: World) -> Command:
        return Command()


@pytest.mark.parametrize(
    ("kind", "required", "limit_s"),
    [("box_transfer", 1, 120.0), ("sort", 4, 120.0), ("palletize", 4, 180.0)],
)
def test_a_trial_asks_what_its_task_asks(kind: str, required: int, limit_s: float) -> None:
    task = load_task(kind)
    world = WorldConfig()
    config = dataclasses.replace(
        SessionConfig(world=world),
        task=TaskConfig(kind=kind, mode="collection", time_limit_s=120.0, countdown_s=0.0),
    )
    runner = SessionRunner(config, Simulation(world, task.scene()), _Still(), max_trials=1)
    runner.start()
    spec = runner.current
    assert spec is not None and (spec.required_boxes, spec.time_limit_s) == (required, limit_s)
    assert runner.hud().required_boxes == required  # what the operator is told


def test_a_session_limit_longer_than_the_tasks_least_is_kept() -> None:
    task = load_task("palletize")
    world = WorldConfig()
    config = dataclasses.replace(
        SessionConfig(world=world),
        task=TaskConfig(kind="palletize", mode="collection", time_limit_s=300.0, countdown_s=0.0),
    )
    runner = SessionRunner(config, Simulation(world, task.scene()), _Still(), max_trials=1)
    runner.start()
    spec = runner.current
    assert spec is not None and spec.time_limit_s == 300.0


def test_the_palletize_environment_is_registered_and_truncates_at_its_tasks_limit() -> None:
    env = gymnasium.make(ENV_IDS["palletize"])
    assert env.spec is not None and env.spec.max_episode_steps == 3600  # 180 s at 20 frames/s
    unwrapped = env.unwrapped
    assert isinstance(unwrapped, BoxTransferEnv)
    assert unwrapped._max_episode_steps == 3600  # LeRobot reads it
    env.close()
    box = gymnasium.make(ENV_IDS["box_transfer"])
    assert box.spec is not None and box.spec.max_episode_steps == 2400
    box.close()

"""``workcell/BoxTransfer-v0``: Gymnasium's checker, spaces = features, replaying a trial."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path
from typing import Any

import gymnasium
import numpy as np
import pyarrow.parquet as pq  # type: ignore[import-untyped, unused-ignore]
import pytest
from gymnasium.utils.env_checker import check_env

from tests.export.stores import Stores
from workcell.control.command import ArmCommand, BaseTwist, Command
from workcell.envs import ENV_ID, MAX_EPISODE_STEPS, register
from workcell.envs.actions import action_from_command, command_from_action
from workcell.envs.box_transfer import BoxTransferEnv
from workcell.envs.config import BoxTransferConfig
from workcell.export.options import ImageSize
from workcell.record.store import Store

UNBOUNDED = "ignore:.*(infinity|symmetric and normalized|not having a spec).*:UserWarning"
TRACK_TOLERANCE_M = 0.05
"""How far the replayed base may drift from the recorded one (the recorder keeps one
command per frame while the expert gave one per control step)."""
ENVIRONMENT = "observation.environment_state"
DELIVERY_FRAMES = 10
"""How many frames (0.5 s) the replayed delivery may come before the recorded one."""


def _episode(root: Path, index: int) -> dict[str, Any]:
    table = pq.read_table(root / "data/chunk-000/file-000.parquet")
    rows = table.filter(table["episode_index"].to_numpy() == index)
    return {name: np.array(rows[name].to_pylist()) for name in rows.column_names}


def _provenance(root: Path) -> list[dict[str, Any]]:
    rows: list[dict[str, Any]] = pq.read_table(
        root / "meta/workcell_provenance.parquet"
    ).to_pylist()
    return rows


@pytest.mark.filterwarnings(UNBOUNDED)
def test_passes_gymnasiums_env_checker() -> None:
    check_env(BoxTransferEnv())
    config = BoxTransferConfig(
        render_size=ImageSize(64, 48), cameras=("head_cam",), camera_size=ImageSize(32, 24)
    )
    env = BoxTransferEnv(config, "rgb_array")
    check_env(env)
    obs, _ = env.reset(seed=0)
    assert obs["pixels"]["head_cam"].shape == (24, 32, 3)
    assert obs["pixels"]["head_cam"].dtype == np.uint8
    image = env.render()
    assert image is not None and image.shape == (48, 64, 3)
    env.close()


def test_made_in_a_fresh_process_without_mujoco_gl_it_renders_twice() -> None:
    """``import workcell.envs`` registers the environment and picks EGL when MUJOCO_GL is
    unset, so Gymnasium's checker and repeated renders work in a plain process."""
    code = (
        "import gymnasium, numpy, workcell.envs\n"
        "from gymnasium.utils.env_checker import check_env\n"
        "env = gymnasium.make('workcell/BoxTransfer-v0', render_mode='rgb_array')\n"
        "check_env(env.unwrapped)\n"
        "env.reset(seed=1)\n"
        "images = [env.render() for _ in range(2)]\n"
        "other = gymnasium.make('workcell/BoxTransfer-v0', render_mode='rgb_array')\n"
        "other.reset(seed=1)\n"
        "images.append(other.render())\n"
        "print(env.spec.max_episode_steps, [i.shape for i in images], "
        "bool(numpy.array_equal(images[0], images[2])))\n"
    )
    environment = {
        k: v for k, v in os.environ.items() if k not in ("MUJOCO_GL", "PYOPENGL_PLATFORM")
    }
    done = subprocess.run(
        [sys.executable, "-W", "ignore", "-c", code],
        capture_output=True,
        text=True,
        env=environment,
        timeout=300,
        check=False,
    )
    assert done.returncode == 0, done.stderr[-2000:]
    assert done.stdout.strip() == "2400 [(240, 320, 3), (240, 320, 3), (240, 320, 3)] True"


def test_spaces_are_the_exported_features(lerobot_dir: Path) -> None:
    features = json.loads((lerobot_dir / "meta/info.json").read_text())["features"]
    env = BoxTransferEnv()
    spaces = env.observation_space.spaces
    assert set(spaces) == {"agent_pos", "environment_state"}
    for key, feature in (("agent_pos", "observation.state"), ("environment_state", ENVIRONMENT)):
        assert list(spaces[key].shape or ()) == features[feature]["shape"]
    assert list(env.action_space.shape) == features["action"]["shape"]
    actions = np.array(pq.read_table(lerobot_dir / "data").column("action").to_pylist())
    assert np.all(env.action_space.low <= actions.min(axis=0))
    assert np.all(actions.max(axis=0) <= env.action_space.high)


def test_replaying_an_exported_expert_trial_delivers_the_box(
    lerobot_dir: Path, recorded: Stores
) -> None:
    origin = _provenance(lerobot_dir)[0]
    assert origin["outcome"] == "success"
    with Store.open(recorded.mixed, writer=False) as store:
        session = next(s for s in store.sessions() if s.session_id == origin["session_id"])
    episode = _episode(lerobot_dir, 0)
    env = BoxTransferEnv(session_parameters=session.parameters)
    obs, info = env.reset(seed=origin["trial_seed"])
    assert np.array_equal(obs["agent_pos"], episode["observation.state"][0])
    assert np.array_equal(obs["environment_state"], episode["observation.environment_state"][0])
    rewards = []
    steps = len(episode["action"]) - 1
    for t in range(steps):
        obs, reward, terminated, truncated, info = env.step(episode["action"][t])
        rewards.append(reward)
        drift = np.abs(obs["agent_pos"][:2] - episode["observation.state"][t + 1][:2]).max()
        assert drift < TRACK_TOLERANCE_M, f"base {drift:.3f} m off the record at frame {t + 1}"
        assert not truncated
        if terminated:
            break
    assert terminated  # the box was delivered ...
    assert steps - 1 - t <= DELIVERY_FRAMES  # ... close to when it was in the record
    assert rewards[-1] == 1.0 and sum(rewards) == 1.0
    assert info["boxes_delivered"] == 1 and info["is_success"]
    assert info["t_sim"] == pytest.approx(origin["elapsed_s"], abs=DELIVERY_FRAMES / 20)


def test_time_limit_truncates() -> None:
    env = BoxTransferEnv(BoxTransferConfig(time_limit_s=0.2))
    env.reset(seed=3)
    idle = action_from_command(Command())
    ends = [env.step(idle)[2:4] for _ in range(4)]
    assert ends == [(False, False)] * 3 + [(False, True)]
    assert env.config.max_episode_steps == 4
    default = BoxTransferConfig()
    assert default.max_episode_steps == MAX_EPISODE_STEPS == 2400


def test_actions_and_commands_convert_both_ways() -> None:
    command = Command(  # values exact in float32
        base=BaseTwist(0.5, -0.125, 0.25),
        left=ArmCommand((0.5, 0.25, 1.0), (0.0, 1.0, 0.0, 0.0), True),
        right=ArmCommand((0.375, -0.25, 0.875), (0.5, 0.5, 0.5, 0.5), False),
        close_left=1.0,
        close_right=0.25,
        head=(0.125, 0.375),
    )
    assert command_from_action(action_from_command(command)) == command
    zero = command_from_action(np.zeros(23))
    assert zero.left.quaternion == (1.0, 0.0, 0.0, 0.0) and not zero.left.follow


def test_importing_the_package_registers_the_environment() -> None:
    code = (
        "import sys, workcell; print('gymnasium' in sys.modules); "
        "import gymnasium, workcell.envs; print('workcell/BoxTransfer-v0' in gymnasium.registry)"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert done.stdout.split() == ["False", "True"]
    register()  # again: changes nothing
    env = gymnasium.make(ENV_ID)
    assert env.unwrapped.spec is not None and env.unwrapped.spec.id == ENV_ID
    assert env.spec is not None and env.spec.max_episode_steps == MAX_EPISODE_STEPS
    env.close()
    made = gymnasium.make("workcell.envs:workcell/BoxTransfer-v0")
    assert isinstance(made.unwrapped, BoxTransferEnv)
    made.close()


def test_every_built_in_task_has_an_environment_id_of_its_own() -> None:
    from workcell.envs import ENV_IDS
    from workcell.tasks.registry import BUILT_IN

    assert ENV_IDS["box_transfer"] == ENV_ID
    assert set(ENV_IDS) == set(BUILT_IN)
    for name, registered_id in ENV_IDS.items():
        env = gymnasium.make(registered_id)
        assert isinstance(env.unwrapped, BoxTransferEnv)
        assert env.unwrapped.task.name == name
        assert env.unwrapped.config.session.task.kind == name
        env.close()

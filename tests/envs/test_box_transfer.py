"""``workcell/BoxTransfer-v0``: Gymnasium's checker, spaces = features, replaying a trial."""

from __future__ import annotations

import json
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
from workcell.envs import ENV_ID, register
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
    env = BoxTransferEnv(BoxTransferConfig(render_size=ImageSize(64, 48)), "rgb_array")
    check_env(env)
    env.reset(seed=0)
    image = env.render()
    assert image is not None and image.shape == (48, 64, 3)
    env.close()


def test_spaces_are_the_exported_features(lerobot_dir: Path) -> None:
    features = json.loads((lerobot_dir / "meta/info.json").read_text())["features"]
    env = BoxTransferEnv()
    spaces = env.observation_space.spaces
    for key, feature in (("state", "observation.state"), ("environment_state", ENVIRONMENT)):
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
    assert np.array_equal(obs["state"], episode["observation.state"][0])
    assert np.array_equal(obs["environment_state"], episode["observation.environment_state"][0])
    rewards = []
    steps = len(episode["action"]) - 1
    for t in range(steps):
        obs, reward, terminated, truncated, info = env.step(episode["action"][t])
        rewards.append(reward)
        drift = np.abs(obs["state"][:2] - episode["observation.state"][t + 1][:2]).max()
        assert drift < TRACK_TOLERANCE_M, f"base {drift:.3f} m off the record at frame {t + 1}"
        assert not truncated
        if terminated:
            break
    assert terminated  # the box was delivered ...
    assert steps - 1 - t <= DELIVERY_FRAMES  # ... close to when it was in the record
    assert rewards[-1] == 1.0 and sum(rewards) == 1.0
    assert info["boxes_delivered"] == 1
    assert info["t_sim"] == pytest.approx(origin["elapsed_s"], abs=DELIVERY_FRAMES / 20)


def test_time_limit_truncates() -> None:
    env = BoxTransferEnv(BoxTransferConfig(time_limit_s=0.2))
    env.reset(seed=3)
    idle = action_from_command(Command())
    ends = [env.step(idle)[2:4] for _ in range(4)]
    assert ends == [(False, False)] * 3 + [(False, True)]


def test_actions_and_commands_convert_both_ways() -> None:
    command = Command(  # values exact in float32
        base=BaseTwist(0.5, -0.125, 0.25),
        left=ArmCommand((0.5, 0.25, 1.0), (0.0, 1.0, 0.0, 0.0), True),
        right=ArmCommand((0.375, -0.25, 0.875), (0.5, 0.5, 0.5, 0.5), False),
        gripper_left=1.0,
        gripper_right=0.25,
        head=(0.125, 0.375),
    )
    assert command_from_action(action_from_command(command)) == command
    zero = command_from_action(np.zeros(23))
    assert zero.left.quaternion == (1.0, 0.0, 0.0, 0.0) and not zero.left.follow


def test_registration_is_explicit() -> None:
    code = (
        "import sys, workcell, workcell.envs; "
        "print('gymnasium' in sys.modules); "
        "import gymnasium; print('workcell/BoxTransfer-v0' in gymnasium.registry)"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert done.stdout.split() == ["False", "False"]
    register()
    register()
    env = gymnasium.make(ENV_ID)
    assert env.unwrapped.spec is not None and env.unwrapped.spec.id == ENV_ID
    env.close()
    made = gymnasium.make("workcell.envs.registered:workcell/BoxTransfer-v0")
    assert isinstance(made.unwrapped, BoxTransferEnv)
    made.close()

"""The learning loop with the real LeRobot: train on an export, load the checkpoint with
``lerobot``, drive recorded sessions with the policy, audit them beside the expert's; the
environment's observations become the export's features through LeRobot's own code."""

from __future__ import annotations

import json
import os
import shutil
import signal
import sqlite3
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from tests.export.conftest import CAMERAS, SIZE
from tests.export.stores import Stores
from tests.learn_extra import require_learn_extra
from workcell.cli.train import evaluation_seed
from workcell.envs.box_transfer import BoxTransferEnv
from workcell.envs.config import BoxTransferConfig
from workcell.export.features import STATE_NAMES
from workcell.learn.checkpoint import PolicyCheckpoint
from workcell.record.verify import verify_store

TINY_ACT = (
    "--lerobot=--policy.dim_model=32",
    "--lerobot=--policy.dim_feedforward=64",
    "--lerobot=--policy.n_heads=2",
    "--lerobot=--policy.latent_dim=8",
)
"""A model small enough to train a few steps in seconds (the defaults are for real use)."""


def _workcell(*args: str, timeout: float = 600) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "workcell", *args],
        capture_output=True,
        text=True,
        timeout=timeout,
        check=False,
    )


@pytest.fixture(scope="module")
def trained(lerobot_dir: Path, tmp_path_factory: pytest.TempPathFactory) -> Path:
    """``workcell train`` for 3 steps on the mixed store's export: the output directory."""
    require_learn_extra()
    out = tmp_path_factory.mktemp("train") / "tiny-act"
    done = _workcell(
        "train", "--dataset", str(lerobot_dir), "--out", str(out), "--steps", "3", *TINY_ACT
    )
    assert done.returncode == 0, done.stderr[-3000:] + done.stdout[-2000:]
    command = "OMP_NUM_THREADS=1 MKL_NUM_THREADS=1 lerobot-train --dataset.repo_id=local/dataset"
    assert command in done.stdout  # one torch thread unless told otherwise
    shown = [line.split("]")[1].split("  ")[0] for line in done.stderr.splitlines() if "]" in line]
    assert shown == [" step 1/3", " step 2/3", " step 3/3"]  # each step, not stdout a terminal
    assert (
        f"workcell collect --operator policy:{out} --world D0 --mode collection --trials 200 "
        f"--seed {evaluation_seed(lerobot_dir)} --condition new-worlds --store eval.sqlite"
    ) in done.stdout  # the world its demonstrations came from
    assert (
        f"workcell collect --operator policy:{out} --world D0 --mode collection --trials 1 "
        "--seed 0 --condition own-worlds --store eval.sqlite"
    ) in done.stdout  # and the very worlds of its first session's demonstrations
    assert (out / "train.log").is_file() and sorted(p.name for p in out.parent.iterdir()) == [
        "tiny-act"
    ]
    # a checkpoint after every step of 3 (a tenth of the run), the newest kept
    assert sorted(p.name for p in (out / "checkpoints").iterdir()) == ["000003", "last"]
    return out


def test_lerobot_loads_the_checkpoint(trained: Path, lerobot_dir: Path) -> None:
    from lerobot.configs.policies import PreTrainedConfig
    from lerobot.policies.act.modeling_act import ACTPolicy
    from lerobot.policies.factory import make_pre_post_processors

    checkpoint = PolicyCheckpoint.locate(trained)
    policy = ACTPolicy.from_pretrained(str(checkpoint.path))
    config = PreTrainedConfig.from_pretrained(str(checkpoint.path))
    preprocessor, postprocessor = make_pre_post_processors(
        config, pretrained_path=str(checkpoint.path)
    )
    info = json.loads((lerobot_dir / "meta/info.json").read_text())
    assert set(policy.config.input_features) == {
        "observation.state",
        "observation.environment_state",
    }
    for key, feature in policy.config.input_features.items():
        assert list(feature.shape) == info["features"][key]["shape"]
    assert list(policy.config.output_features["action"].shape) == [23]
    assert preprocessor is not None and postprocessor is not None


def test_a_policy_drives_recorded_sessions_audited_beside_the_expert(
    trained: Path, recorded: Stores, tmp_path: Path
) -> None:
    store = tmp_path / "both.sqlite"
    shutil.copy(recorded.mixed, store)
    done = _workcell(
        "collect",
        "--operator",
        f"policy:{trained}",
        "--mode",
        "collection",
        "--trials",
        "2",
        "--seed",
        "7",
        "--set",
        "task.time_limit_s=1.5",
        "--store",
        str(store),
    )
    assert done.returncode == 0, done.stderr[-3000:]
    assert done.stdout.split()[0] == "index"  # the table first, no LeRobot chatter
    assert "Loading weights" not in done.stdout + done.stderr
    assert done.stdout.count(" timeout ") + done.stdout.count(" success ") == 2
    assert verify_store(store) == []
    checkpoint = PolicyCheckpoint.locate(trained)
    with sqlite3.connect(store) as db:
        operators = [row[0] for row in db.execute("SELECT operator_id FROM sessions")]
        frames = db.execute(
            "SELECT COUNT(*) FROM frames JOIN sessions USING (session_id) WHERE operator_id = ?",
            (checkpoint.operator_id,),
        ).fetchone()[0]
    assert operators.count(checkpoint.operator_id) == 1 and "expert" in operators
    assert frames == 2 * (1.5 * 20 + 1)
    report = tmp_path / "report"
    audited = _workcell("audit", "--store", str(store), "--out", str(report))
    assert audited.returncode == 0, audited.stderr
    summary = json.loads((report / "summary.json").read_text())
    groups = {g["value"]: g for g in summary["groups"]["operator"]}
    assert groups[checkpoint.operator_id]["counts"]["raw"] == 2
    assert groups[checkpoint.operator_id]["success_rate"]["n"] == 2
    assert groups["expert"]["counts"]["raw"] == 3  # the mixed store's collect sessions
    assert checkpoint.operator_id in (report / "report.html").read_text()
    shown = audited.stdout.splitlines()
    assert f"  operator {checkpoint.operator_id}: 2 trials" in "\n".join(shown)
    assert any(line.startswith("  operator expert: 3 trials") for line in shown)


def test_the_policy_observes_what_the_env_and_the_export_hold(
    trained: Path, recorded: Stores, tmp_path: Path
) -> None:
    """The policy session's recorded frame 0 is the env's first observation of the same
    trial seed, value for value. (With --verbose, LeRobot's loading message is shown.)"""
    store = tmp_path / "policy.sqlite"
    done = _workcell(
        "collect", "--operator", f"policy:{trained}", "--trials", "1", "--seed", "11",
        "--mode", "collection", "--set", "task.time_limit_s=0.5", "--store", str(store),
        "--verbose",
    )  # fmt: skip
    assert done.returncode == 0, done.stderr[-3000:]
    assert done.stdout.startswith("Loading weights from local directory\nindex ")
    with sqlite3.connect(store) as db:
        seed = json.loads(
            db.execute("SELECT payload_json FROM events WHERE kind = 'trial_started'").fetchone()[0]
        )["trial_seed"]
        first = db.execute(
            f"SELECT {', '.join(STATE_NAMES)} FROM frames WHERE frame_index = 0"
        ).fetchone()
    env = BoxTransferEnv()
    observation, _ = env.reset(seed=seed)
    assert np.array_equal(observation["agent_pos"], np.array(first, dtype=np.float32))


def test_env_observations_become_the_export_features_through_lerobot(
    lerobot_video_dir: Path,
) -> None:
    require_learn_extra()
    from lerobot.datasets.lerobot_dataset import LeRobotDataset
    from lerobot.envs.utils import preprocess_observation

    dataset = LeRobotDataset("local/video", root=lerobot_video_dir, video_backend="pyav")
    provenance = json.loads((lerobot_video_dir / "meta/workcell_provenance.json").read_text())
    episode = provenance["episodes"][0]
    env = BoxTransferEnv(BoxTransferConfig(cameras=CAMERAS, camera_size=SIZE))
    observation, _ = env.reset(seed=episode["trial_seed"])
    batch: dict[str, Any] = preprocess_observation(observation)
    sample = dataset[0]
    observed = {k for k in sample if k.startswith("observation.")}
    assert set(batch) == observed
    for key in observed:
        assert tuple(batch[key].shape[1:]) == tuple(sample[key].shape), key
        stored = list(dataset.meta.features[key]["shape"])  # images: (height, width, channels)
        shape = list(sample[key].shape)
        assert shape == (stored[-1:] + stored[:-1] if len(stored) == 3 else stored), key
    for key in ("observation.state", "observation.environment_state"):
        assert np.array_equal(batch[key][0].numpy(), sample[key].numpy()), key
    for camera in CAMERAS:
        key = f"observation.images.{camera}"
        difference = (batch[key][0] - sample[key]).abs().mean().item()
        # H.264 costs several levels per pixel (10 of 255 = 0.04) on the textured floor
        assert difference < 0.04, f"{key}: mean difference {difference:.3f} (video coding)"
    env.close()


def test_a_policy_for_another_world_is_refused(trained: Path, tmp_path: Path) -> None:
    done = _workcell(
        "collect", "--operator", f"policy:{trained}", "--trials", "1",
        "--set", "world.feeder.pool_size=2", "--store", str(tmp_path / "s.sqlite"),
    )  # fmt: skip
    assert done.returncode == 2
    assert "does not fit this session" in done.stderr
    assert "observation.environment_state of shape" in done.stderr


@pytest.mark.slow
def test_a_training_cut_short_leaves_its_log_and_a_checkpoint_that_drives(
    lerobot_dir: Path, tmp_path: Path
) -> None:
    """``workcell train`` writes OUT/train.log from its start (no file beside OUT); killed
    while it trains, it has left a checkpoint of a tenth of the run, which a session drives
    with."""
    require_learn_extra()
    out = tmp_path / "cut"
    process = subprocess.Popen(
        [sys.executable, "-m", "workcell", "train", "--dataset", str(lerobot_dir),
         "--out", str(out), "--steps", "200", "--batch-size", "4", *TINY_ACT],
        stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True,
    )  # fmt: skip
    last = out / "checkpoints" / "last"
    log = out / "train.log"
    try:
        while process.poll() is None and not log.exists():
            time.sleep(0.05)
        # there from the start: before LeRobot (importing torch) has logged a line
        assert process.poll() is None and "INFO " not in log.read_text()
        assert log.read_text().startswith("$ OMP_NUM_THREADS=1 ")
        while process.poll() is None and not last.exists():
            time.sleep(0.2)
        assert process.poll() is None, "the training ended before its first checkpoint"
        assert (out / "train.log").is_file()
        assert [p.name for p in tmp_path.iterdir()] == ["cut"]  # nothing hidden beside OUT
    finally:
        os.killpg(process.pid, signal.SIGKILL)
        process.wait()
    kept = int(last.resolve().name)
    assert kept < 200 and kept % 20 == 0  # before the last step: every tenth of 200 steps
    store = tmp_path / "s.sqlite"
    drove = _workcell(
        "collect", "--operator", f"policy:{out}", "--trials", "1", "--mode", "collection",
        "--set", "task.time_limit_s=0.5", "--store", str(store),
    )  # fmt: skip
    assert drove.returncode == 0, drove.stderr[-3000:]
    assert verify_store(store) == []


@pytest.mark.slow
def test_a_training_that_never_starts_leaves_its_log_in_out_for_the_next_to_replace(
    lerobot_dir: Path, tmp_path: Path
) -> None:
    require_learn_extra()
    out = tmp_path / "bad"
    argv = ["train", "--dataset", str(lerobot_dir), "--out", str(out), "--steps", "2"]
    failed = _workcell(*argv, "--lerobot=--no_such_option=1")
    assert failed.returncode == 2
    (error,) = [line for line in failed.stderr.splitlines() if line.startswith("workcell: error")]
    assert error.endswith(f"the whole log is in {out / 'train.log'}")
    assert [p.name for p in out.iterdir()] == ["train.log"]
    assert "no_such_option" in (out / "train.log").read_text()
    done = _workcell(*argv, *TINY_ACT)  # the same --out: the failed start's log is replaced
    assert done.returncode == 0, done.stderr[-3000:]
    assert "no_such_option" not in (out / "train.log").read_text()


@pytest.mark.slow
def test_a_diffusion_policy_trains_and_drives(lerobot_dir: Path, tmp_path: Path) -> None:
    """``--policy diffusion``, with options passed on to LeRobot overriding the defaults."""
    require_learn_extra()
    out = tmp_path / "tiny-diffusion"
    done = _workcell(
        "train", "--dataset", str(lerobot_dir), "--out", str(out), "--policy", "diffusion",
        "--steps", "2", "--batch-size", "4", "--lerobot=--policy.down_dims=[16,32]",
        "--lerobot=--policy.diffusion_step_embed_dim=16",
    )  # fmt: skip
    assert done.returncode == 0, done.stderr[-3000:] + done.stdout[-2000:]
    checkpoint = PolicyCheckpoint.locate(out)
    config = json.loads((checkpoint.path / "config.json").read_text())
    assert config["type"] == "diffusion" and config["down_dims"] == [16, 32]
    assert config["noise_scheduler_type"] == "DDIM"  # the CPU default, kept
    store = tmp_path / "s.sqlite"
    drove = _workcell(
        "collect", "--operator", f"policy:{out}", "--trials", "1", "--mode", "collection",
        "--set", "task.time_limit_s=0.5", "--store", str(store),
    )  # fmt: skip
    assert drove.returncode == 0, drove.stderr[-3000:]
    assert verify_store(store) == []

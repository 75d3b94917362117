"""``workcell train``'s options, LeRobot's command line, progress and checkpoint lookup
(none of it needs the learn extra)."""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import pytest

from workcell.cli.collect_operator import with_operator_id
from workcell.cli.main import main
from workcell.cli.train import evaluation_seed, parse_episodes
from workcell.errors import ConfigError
from workcell.learn.checkpoint import LAST_CHECKPOINT, PolicyCheckpoint
from workcell.learn.errors import LearnError
from workcell.learn.train import ProgressReader, check_dataset
from workcell.learn.train_options import TrainOptions, lerobot_arguments
from workcell.session.config import SessionConfig


def test_lerobot_arguments_are_offline_cpu_state_only_defaults(tmp_path: Path) -> None:
    options = TrainOptions(dataset=tmp_path / "ds", out=tmp_path / "run", episodes=(0, 2))
    arguments = lerobot_arguments(options, "cpu", has_videos=True)
    assert f"--dataset.root={tmp_path / 'ds'}" in arguments
    for expected in (
        "--policy.type=act",
        "--policy.device=cpu",
        "--policy.push_to_hub=false",
        "--policy.pretrained_backbone_weights=null",
        "--wandb.enable=false",
        "--eval_freq=0",
        "--steps=10000",
        "--save_freq=10000",
        "--dataset.episodes=[0,2]",
        "--dataset.video_backend=pyav",
    ):
        assert expected in arguments
    extra = TrainOptions(tmp_path / "ds", tmp_path / "run", extra=("--policy.dim_model=64",))
    assert lerobot_arguments(extra, "cpu", has_videos=False)[-1] == "--policy.dim_model=64"
    diffusion = lerobot_arguments(TrainOptions(tmp_path, tmp_path, "diffusion"), "cpu", False)
    assert "--policy.noise_scheduler_type=DDIM" in diffusion


def test_bad_train_options_name_what_is_allowed(tmp_path: Path) -> None:
    with pytest.raises(ConfigError) as raised:
        TrainOptions(tmp_path, tmp_path, "bc", steps=0, episodes=(), extra=("x",))  # type: ignore[arg-type]
    problems = "\n".join(raised.value.problems)
    for part in ("--policy = 'bc'", "--steps = 0", "--episodes = ()", "--lerobot 'x'"):
        assert part in problems
    assert parse_episodes("0-2,5, 4") == (0, 1, 2, 4, 5)
    for bad in ("a", "3-1", "-1"):
        with pytest.raises(ConfigError):
            parse_episodes(bad)


def test_train_refuses_what_is_not_a_dataset_and_a_used_output(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(["train", "--dataset", str(tmp_path / "none"), "--out", str(tmp_path / "o")]) == 2
    assert "no LeRobotDataset there" in capsys.readouterr().err
    (tmp_path / "ds" / "meta").mkdir(parents=True)
    (tmp_path / "ds" / "meta" / "info.json").write_text(json.dumps({"codebase_version": "v2.1"}))
    with pytest.raises(LearnError, match=r"version 'v2\.1'"):
        check_dataset(tmp_path / "ds")
    (tmp_path / "ds" / "meta" / "info.json").write_text(json.dumps({"codebase_version": "v3.0"}))
    (tmp_path / "used").mkdir()
    (tmp_path / "used" / "file").write_text("x")
    code = main(["train", "--dataset", str(tmp_path / "ds"), "--out", str(tmp_path / "used")])
    assert code == 2
    assert "exists and is not empty" in capsys.readouterr().err


def test_progress_reads_tqdm_and_the_log() -> None:
    reader = ProgressReader(2000)
    bar = "Training:  62%|#####  | 1234/2000 [01:00<00:30, 3.1step/s]"
    log = "INFO 2026-12-01 ot_train.py:435 step:1K smpl:39K ep:80 epch:0.5 loss:0.512 grdn:3"
    first = reader.read(log.replace("1K", "100"), 10.0)
    assert first is not None and first.step == 100 and first.steps_per_s == 0.0
    assert reader.read(bar, 20.0) is None
    later = reader.read(log, 20.0)
    assert later is not None and later.step == 1234 and later.loss == 0.512
    assert later.steps_per_s == pytest.approx(113.4)
    assert later.remaining_s == pytest.approx(766 / 113.4)


def _fake_checkpoint(root: Path, policy_type: str = "act") -> Path:
    """A pretrained-model directory as LeRobot lays it out (contents are not loaded)."""
    root.mkdir(parents=True)
    (root / "config.json").write_text(json.dumps({"type": policy_type}))
    (root / "model.safetensors").write_bytes(b"weights")
    return root


def test_a_checkpoint_is_found_from_the_training_output(tmp_path: Path) -> None:
    run = tmp_path / "expert 200 demos"
    _fake_checkpoint(run / "checkpoints" / "000010" / "pretrained_model")
    (run / "checkpoints" / "last").symlink_to("000010")
    for given in (run, run / "checkpoints" / "000010", run / LAST_CHECKPOINT):
        found = PolicyCheckpoint.locate(given)
        assert found.path == (run / "checkpoints" / "000010" / "pretrained_model").resolve()
        assert found.name == "expert 200 demos"
        assert found.operator_id == "policy-act-expert_200_demos-" + found.weights_sha256[:12]
    for run_name, expected in (("act", "policy-act-"), ("ACT-200 demos", "policy-act-200_demos-")):
        named = PolicyCheckpoint(run, "act", "cd" * 32, run_name)
        assert named.operator_id == expected + "cd" * 6  # the type once
    actor = PolicyCheckpoint(run, "act", "cd" * 32, "actor")
    assert actor.operator_id == "policy-act-actor-" + "cd" * 6
    long_name = PolicyCheckpoint(run, "diffusion", "ab" * 32, "x" * 100)
    assert len(long_name.operator_id) == 64
    assert SessionConfig(operator_id=long_name.operator_id).operator_id.endswith("abababababab")
    with pytest.raises(LearnError, match="no LeRobot pretrained model there"):
        PolicyCheckpoint.locate(tmp_path)


def test_sessions_are_named_after_their_operator() -> None:
    def named(operator_id: str | None, skill: float = 1.0, config_id: str = "anonymous") -> str:
        args = argparse.Namespace(operator_id=operator_id, skill=skill)
        config = SessionConfig(operator_id=config_id)
        return with_operator_id(config, args, None).operator_id

    assert named(None) == "expert"
    assert named(None, 0.25) == "expert-skill0.25"
    assert named("alice", config_id="alice") == "alice"  # chosen with --operator-id
    assert named(None, config_id="bob") == "bob"  # chosen in the configuration


def test_collect_refuses_a_policy_that_is_not_there(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    store = tmp_path / "s.sqlite"
    code = main(["collect", "--operator", f"policy:{tmp_path}", "--store", str(store)])
    assert code == 2
    err = capsys.readouterr().err
    assert "no LeRobot pretrained model there" in err and len(err.splitlines()) == 1
    assert main(["collect", "--operator", "human", "--store", str(store)]) == 2
    assert "must be expert or policy:PATH" in capsys.readouterr().err
    assert not store.exists()


def test_the_suggested_evaluation_seed_is_one_no_session_of_the_dataset_used(
    tmp_path: Path,
) -> None:
    meta = tmp_path / "meta"
    meta.mkdir()
    assert evaluation_seed(tmp_path) == 1000  # no provenance: the default
    sessions = {f"s{seed}": {"seed": seed} for seed in (0, 1000, 1001, 7)}
    (meta / "workcell_provenance.json").write_text(json.dumps({"sessions": sessions}))
    assert evaluation_seed(tmp_path) == 1002

"""``workcell train``'s options, LeRobot's command line, progress and checkpoint lookup
(none of it needs the learn extra)."""

from __future__ import annotations

import argparse
import itertools
import json
import sqlite3
import sys
from pathlib import Path

import pytest

from workcell.cli.collect_operator import with_operator_id
from workcell.cli.main import main
from workcell.cli.train import (
    _ProgressBar,
    evaluation_hint,
    evaluation_seed,
    own_worlds,
    parse_episodes,
)
from workcell.errors import ConfigError
from workcell.learn.checkpoint import LAST_CHECKPOINT, PolicyCheckpoint
from workcell.learn.errors import LearnError
from workcell.learn.policy_operator import library_output
from workcell.learn.train import ProgressReader, TrainProgress, check_dataset, thread_environment
from workcell.learn.train_options import TrainOptions, lerobot_arguments
from workcell.session.config import SessionConfig
from workcell.tasks.registry import task_class
from workcell.tasks.worlds import world_overrides


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
        "--save_freq=1000",  # a checkpoint every tenth of the run
        "--log_freq=10",  # progress every 10 steps
        "--num_workers=1",
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


def test_the_default_is_one_torch_thread_and_a_checkpoint_every_tenth(tmp_path: Path) -> None:
    options = TrainOptions(tmp_path / "ds", tmp_path / "run", steps=2500)
    assert thread_environment(options) == {"OMP_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}
    assert "--save_freq=250" in lerobot_arguments(options, "cpu", has_videos=False)
    kept = TrainOptions(tmp_path / "ds", tmp_path / "run", steps=2500, save_every=100, threads=2)
    assert "--save_freq=100" in lerobot_arguments(kept, "cpu", has_videos=False)
    assert thread_environment(kept)["OMP_NUM_THREADS"] == "2"
    logged = TrainOptions(tmp_path, tmp_path, extra=("--log_freq=50",))
    assert logged.log_every == 50
    assert thread_environment(TrainOptions(tmp_path, tmp_path, threads=0)) == {}  # torch's
    with pytest.raises(ConfigError, match="--threads = -1"):
        TrainOptions(tmp_path, tmp_path, threads=-1)


def _lerobot_log_line(step: int, loss: float) -> str:
    """LeRobot's log line after ``step`` (its ``MetricsTracker``: the step rounded as
    ``format_big_number`` rounds it)."""
    shown = f"{step / 1000:.0f}K" if step >= 1000 else str(step)
    return (
        f"INFO 2026-12-01 10:00:00 ot_train.py:435 step:{shown} smpl:{32 * step} ep:8 loss:{loss}"
    )


def test_progress_shows_the_true_step_with_its_own_loss_and_rate() -> None:
    """LeRobot logs every 100th step of this run as ``step:2K`` from step 1500 on; the
    report is of step 1500, with that line's loss and the rate up to it."""
    reader = ProgressReader(2000, log_every=100)
    reports = [
        reader.read(_lerobot_log_line(step, step / 1e4), 10.0 + step / 2)
        for step in range(100, 1600, 100)
    ]
    assert reader.read("Training:  62%|#####  | 1990/2000 [01:00<00:30, 3.1step/s]", 99.0) is None
    last = reports[-1]
    assert last is not None and reports[0] is not None
    assert (last.step, last.loss) == (1500, 0.15)
    assert reports[0].step == 100 and reports[0].steps_per_s == 0.0
    assert last.steps_per_s == pytest.approx(2.0)  # 1400 steps in 700 s
    assert last.remaining_s == pytest.approx(250.0)


def test_without_a_terminal_progress_shows_at_once_then_each_tenth_and_minute(
    capsys: pytest.CaptureFixture[str],
) -> None:
    bar = _ProgressBar()
    assert not bar.live  # pytest captures stderr
    for step in range(10, 2510, 10):  # every 10 steps at 2 s a step, after 30 s of set-up
        bar.show(TrainProgress(step, 10_000, 0.5, 30.0 + 2 * step, 0.5))
    lines = capsys.readouterr().err.splitlines()
    shown = [int(line.split("step ")[1].split("/")[0]) for line in lines]
    assert shown[0] == 10  # the first report, at once
    assert {1000, 2000} <= set(shown)  # each tenth
    assert all(0 < b - a <= 30 for a, b in itertools.pairwise(shown))  # a line a minute
    assert len(shown) < 100  # of 250 reports


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
    def named(
        operator_id: str | None, skill: float = 1.0, config_id: str = "anonymous", noise: float = 0
    ) -> str:
        args = argparse.Namespace(
            operator="expert", operator_id=operator_id, skill=skill, corrector=None,
            base_noise=noise,
        )  # fmt: skip
        config = SessionConfig(operator_id=config_id)
        return with_operator_id(config, args, None).operator_id

    assert named(None) == "expert"
    assert named(None, 0.25) == "expert-skill0.25"
    assert named(None, noise=0.1) == "expert-noise0.1"  # collect --base-noise
    assert named(None, 0.5, noise=0.2) == "expert-skill0.5-noise0.2"
    assert named("alice", config_id="alice") == "alice"  # chosen with --operator-id
    assert named(None, config_id="bob") == "bob"  # chosen in the configuration
    # with a scripted corrector: a session the corrector watches, the policy its driver
    corrected = with_operator_id(
        SessionConfig(),
        argparse.Namespace(
            operator="policy:act", operator_id=None, skill=1.0, corrector="expert", base_noise=0
        ),
        None,
    )
    assert (corrected.operator_id, corrected.driver) == ("expert", "policy:act")


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


def _provenance(dataset: Path, *parameters: dict[str, object]) -> None:
    sessions = {f"s{i}": {"seed": i, "parameters": p} for i, p in enumerate(parameters)}
    (dataset / "meta").mkdir(parents=True, exist_ok=True)
    (dataset / "meta" / "workcell_provenance.json").write_text(json.dumps({"sessions": sessions}))


def _world(name: str) -> dict[str, object]:
    ranges = world_overrides(task_class("box_transfer").worlds[name])  # type: ignore[index]
    section = {key.rpartition(".")[2]: value for key, value in ranges.items()}
    return {"task": {"kind": "box_transfer"}, "world": {"randomization": section}}


def test_the_closing_hint_evaluates_in_the_demonstrations_worlds(tmp_path: Path) -> None:
    """Demonstrations recorded in D1 are evaluated in D1 (new seeds); ranges of no named
    world are set one by one; without provenance the default world is suggested."""
    out = tmp_path / "act"
    _provenance(tmp_path / "d1", _world("D1"), _world("D1"))
    hint = evaluation_hint(tmp_path / "d1", out)
    assert hint[0].startswith("evaluate it in new worlds of its demonstrations' kind (--world D1")
    assert hint[1] == (
        f"  workcell collect --operator policy:{out} --world D1 --mode collection --trials 200 "
        "--seed 1000 --store eval.sqlite"
    )
    assert hint[2] == "  workcell audit --store eval.sqlite --out report"
    custom = _world("D0")
    custom["world"]["randomization"]["target_shift"] = 0.05  # type: ignore[index]
    _provenance(tmp_path / "mixed", _world("D2"), custom)
    commands = evaluation_hint(tmp_path / "mixed", out)[1:3]
    assert " --world D2 " in commands[0]
    assert " --set world.randomization.target_shift=0.05 --mode" in commands[1]
    (tmp_path / "none").mkdir()
    assert (
        " policy:" + str(out) + " --mode collection" in evaluation_hint(tmp_path / "none", out)[1]
    )


def test_what_libraries_print_while_a_policy_loads_is_dropped_unless_verbose(
    capsys: pytest.CaptureFixture[str],
) -> None:
    for verbose in (False, True):
        with library_output(verbose):
            print("Loading weights from local directory")
            print("a library's warning", file=sys.stderr)
        out, err = capsys.readouterr()
        assert (out, err) == (
            ("Loading weights from local directory\n", "a library's warning\n")
            if verbose
            else ("", "")
        )
    with pytest.raises(LearnError), library_output(verbose=False):
        raise LearnError("errors still raise")


def test_the_closing_hint_replays_the_very_worlds_of_the_demonstrations(
    lerobot_dir: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """Its own-worlds commands meet every exported episode's world (its trial seed), beside
    the new worlds, as two conditions that the audit compares."""
    provenance = json.loads((lerobot_dir / "meta" / "workcell_provenance.json").read_text())
    episodes = provenance["episodes"]
    own = own_worlds(lerobot_dir)
    assert len(own) == len({e["session_id"] for e in episodes}) >= 2
    hint = evaluation_hint(lerobot_dir, tmp_path / "act")
    assert hint[0].startswith("evaluate it in the very worlds of its demonstrations")
    commands = [line.split() for line in hint[1:-1]]
    assert [c[c.index("--condition") + 1] for c in commands] == ["own-worlds"] * len(own) + [
        "new-worlds"
    ]
    assert hint[-1] == "  workcell audit --store eval.sqlite --out report --by condition"
    store = tmp_path / "eval.sqlite"
    for flags, seed, trials in own:  # the expert in the policy's place, briefly
        argv = [*flags, "--mode", "collection", "--trials", str(trials), "--seed", str(seed)]
        argv += ["--set", "task.time_limit_s=0.2", "--store", str(store)]
        assert main(["collect", *argv]) == 0
    capsys.readouterr()
    with sqlite3.connect(store) as db:
        met = {
            json.loads(payload)["trial_seed"]
            for (payload,) in db.execute(
                "SELECT payload_json FROM events WHERE kind = 'trial_started'"
            )
        }
    assert {e["trial_seed"] for e in episodes} <= met

"""The record's task-neutral columns (schema version 5): a collected trial keeps its task,
world, goal, the stage and progress its task's judge gave it, and every frame the judge's
word at its instant; the CSV export carries them. A judge that says failure ends the trial
``failed`` at once."""

from __future__ import annotations

import json
import sqlite3
from pathlib import Path

import numpy as np
import pytest

from tests.tasks.giving_up_task import GIVE_UP_AFTER
from workcell.cli.main import main
from workcell.record import Store
from workcell.record.export_csv import read_csv_export
from workcell.tasks.box_transfer.stages import TASK_STAGES

GIVING_UP = "tests.tasks.giving_up_task:GivingUpTransfer"


def _collect(store: Path, *argv: str) -> None:
    assert main(["collect", "--writer", "inline", "--store", str(store), *argv]) == 0


def test_a_box_transfer_trial_records_its_task_stage_and_progress(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    store = tmp_path / "s.sqlite"
    _collect(store, "--mode", "practice", "--seed", "1", "--world", "D1")
    with Store.open(store, writer=False) as reader:
        (trial,) = reader.trials()
        frames = reader.frames(trial.trial_id)
        (started,) = [e for e in reader.events() if e.kind == "trial_started"]
    assert trial.outcome == "success"
    assert (trial.task, trial.world, trial.stage, trial.progress) == (
        "box_transfer",
        "D1",
        "delivered",
        1.0,
    )
    center = started.payload["conditions"]["target_center"]
    assert trial.goal == {"goal_x": center[0], "goal_y": center[1]}
    # every frame: the judge's word at its instant, never going back, delivered at the end
    order = [TASK_STAGES.index(s) for s in frames["stage"]]
    assert order[0] == 0 and order == sorted(order)
    assert frames["stage"][-1] == "delivered" and frames["stage"][-2] != "delivered"
    assert {"grasped", "lifted", "over_zone"} <= set(frames["stage"])
    progress = frames["progress"]
    assert progress[-1] == 1.0 and (progress[:-1] == 0.0).all()
    # grasped exactly while a box was first held (the judge reads the world the frame shows)
    first_held = int(np.flatnonzero(frames["attached"] >= 0)[0])
    assert order.index(TASK_STAGES.index("grasped")) == first_held
    out = tmp_path / "csv"
    assert main(["export", "--format", "csv", "--store", str(store), "--out", str(out)]) == 0
    exported = read_csv_export(out).tables
    row = {name: values[0] for name, values in exported["trials.csv"].items()}
    assert (row["task"], row["world"], row["stage"], row["progress"]) == (
        "box_transfer",
        "D1",
        "delivered",
        1.0,
    )
    assert json.loads(row["goal_json"]) == trial.goal
    assert list(exported["frames.csv"]["stage"]) == list(frames["stage"])
    np.testing.assert_array_equal(exported["frames.csv"]["progress"], progress)
    assert main(["verify", "--store", str(store)]) == 0
    capsys.readouterr()


def test_a_judge_that_says_failure_ends_the_trial_failed(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    store = tmp_path / "s.sqlite"
    argv = ("--mode", "collection", "--trials", "2", "--seed", "5", "--json")
    _collect(store, "--task", GIVING_UP, *argv)
    printed = [json.loads(line) for line in capsys.readouterr().out.splitlines()]
    assert [r["outcome"] for r in printed] == ["failed", "failed"]
    with Store.open(store, writer=False) as reader:
        trials = reader.trials()
        ended = [e for e in reader.events() if e.kind == "trial_ended"]
        frames = [reader.frames(t.trial_id) for t in trials]
    assert [t.outcome for t in trials] == ["failed", "failed"]
    assert [e.payload["outcome"] for e in ended] == ["failed", "failed"]
    for trial, columns in zip(trials, frames, strict=True):
        # judged at frame instants 1..20: it ends at the 20th, its last frame
        assert trial.elapsed_s == pytest.approx(GIVE_UP_AFTER / 20.0)
        assert trial.n_frames == GIVE_UP_AFTER + 1
        assert trial.completion_time_s is None and trial.score == 0
        assert trial.task == GIVING_UP and trial.stage == "none" and trial.progress == 0.0
        assert trial.included  # a complete outcome: valid, not successful
        assert columns["t_sim"][-1] == pytest.approx(trial.elapsed_s)
    assert main(["audit", "--store", str(store), "--out", str(tmp_path / "audit")]) == 0
    summary = json.loads((tmp_path / "audit" / "summary.json").read_text())
    assert summary["counts"]["complete_failures"] == 2
    assert summary["success_rate"]["n"] == 2 and summary["success_rate"]["successes"] == 0
    # a challenge level whose trial failed is repeated, as after a timeout
    challenge = tmp_path / "c.sqlite"
    _collect(challenge, "--task", GIVING_UP, "--mode", "challenge", "--trials", "3")
    with sqlite3.connect(challenge) as connection:
        rows = connection.execute("SELECT level, outcome FROM trials ORDER BY trial_index")
        assert rows.fetchall() == [(1, "failed")] * 3


def test_a_judge_naming_a_stage_its_task_lacks_is_one_clear_error(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    store = tmp_path / "s.sqlite"
    argv = ["collect", "--writer", "inline", "--store", str(store), "--mode", "practice"]
    assert main([*argv, "--task", "tests.tasks.giving_up_task:StrayStageTransfer"]) != 0
    error = capsys.readouterr().err
    assert "the judge of task stray_stage_transfer says stage 'somewhere'" in error
    assert "not one of its stages ('none', 'touched'" in error

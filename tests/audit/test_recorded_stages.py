"""The audit reads a trial's stage as its task's judge recorded it (schema version 5),
recomputes box transfer's from the frames for a trial recorded before, and reports a
box-transfer trial whose recorded stage its frames contradict."""

from __future__ import annotations

import csv
import json
import sqlite3
from pathlib import Path

from workcell.audit.task_stages import FRAMES_TASK, TASK_STAGES, session_task
from workcell.cli.main import main
from workcell.tasks.box_transfer.task import BoxTransfer
from workcell.tasks.registry import recorded_kind


def _audit(store: Path, out: Path) -> tuple[list[dict[str, str]], dict[str, object]]:
    assert main(["audit", "--store", str(store), "--out", str(out), "--force"]) == 0
    with (out / "trials.csv").open() as file:
        rows = list(csv.DictReader(file))
    summary: dict[str, object] = json.loads((out / "summary.json").read_text())
    return rows, summary


def _findings(summary: dict[str, object]) -> list[dict[str, str]]:
    found = summary["findings"]
    assert isinstance(found, list)
    return [f for f in found if f["kind"] == "stage_mismatch"]


def test_recorded_stages_are_read_recomputed_for_older_trials_and_cross_checked(
    tmp_path: Path,
) -> None:
    store = tmp_path / "s.sqlite"
    argv = ["collect", "--writer", "inline", "--store", str(store), "--mode", "practice"]
    # cut off before the delivery: the stage is read from the frames, not from a delivery
    assert main([*argv, "--seed", "1", "--set", "task.time_limit_s=17"]) == 0
    with sqlite3.connect(store) as connection:
        (recorded,) = connection.execute("SELECT stage FROM trials").fetchone()
        outcome = connection.execute("SELECT outcome FROM trials").fetchone()[0]
    assert outcome == "timeout" and recorded in ("grasped", "lifted", "over_zone")
    rows, summary = _audit(store, tmp_path / "a")
    assert [r["stage_reached"] for r in rows] == [recorded]
    assert _findings(summary) == []  # the judge and the frames agree

    # as a trial recorded before version 5: the stage comes from the frames, the same
    with sqlite3.connect(store) as connection:
        connection.execute("UPDATE trials SET stage = NULL, task = NULL")
    rows, summary = _audit(store, tmp_path / "a")
    assert [r["stage_reached"] for r in rows] == [recorded]
    assert _findings(summary) == []

    # a recorded stage the frames contradict is read as recorded, and reported
    with sqlite3.connect(store) as connection:
        connection.execute("UPDATE trials SET stage = 'none', task = 'box_transfer'")
    rows, summary = _audit(store, tmp_path / "a")
    assert [r["stage_reached"] for r in rows] == ["none"]
    (finding,) = _findings(summary)
    assert finding["message"] == (
        f"recorded stage none (its judge's), but its frames say {recorded}"
    )


def test_the_audit_names_box_transfer_and_reads_a_sessions_task_as_the_registry_does() -> None:
    assert BoxTransfer.name == FRAMES_TASK and BoxTransfer.stages == TASK_STAGES
    cases: tuple[dict[str, object], ...] = (
        {},
        {"task": {"kind": "examples.lift_box:LiftBox"}},
        {"task": {}},
        {"task": "box_transfer"},
        {"task": {"kind": "box_transfer", "mode": "practice"}},
    )
    for parameters in cases:
        assert session_task(parameters) == recorded_kind(parameters)

"""The example task (examples/lift_box, docs/tasks.md) is collected with its expert,
audited and exported without any file outside its folder knowing it."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import pytest
from examples.lift_box.task import LiftBox

from workcell.cli.main import main

LIFT = "examples.lift_box:LiftBox"


def test_the_example_task_is_collected_audited_and_exported(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(["tasks", LIFT]) == 0
    assert capsys.readouterr().out.startswith("lift_box  lift a box off the conveyor")
    store = tmp_path / "lift.sqlite"
    argv = ["collect", "--task", LIFT, "--world", "D1", "--mode", "collection", "--trials", "2"]
    assert main([*argv, "--store", str(store), "--json"]) == 0
    rows = [json.loads(line) for line in capsys.readouterr().out.splitlines()]
    assert [r["outcome"] for r in rows] == ["success", "success"]
    assert all(10.0 < r["elapsed_s"] < 30.0 for r in rows)  # held up, not delivered
    assert main(["audit", "--store", str(store), "--out", str(tmp_path / "audit")]) == 0
    with (tmp_path / "audit" / "trials.csv").open() as file:
        audited = list(csv.DictReader(file))
    assert [t["outcome"] for t in audited] == ["success", "success"]
    # its trials are read among its own stages, as its judge recorded them
    assert [t["stage_reached"] for t in audited] == ["held_up", "held_up"]
    summary = json.loads((tmp_path / "audit" / "summary.json").read_text())
    funnel = summary["task_stages"]["by_task"][LIFT]
    assert funnel["stages"] == list(LiftBox.stages)
    assert funnel["ended_at"] == {"none": 0, "touched": 0, "grasped": 0, "lifted": 0, "held_up": 2}
    assert funnel["reached"]["lifted"] == 2 and funnel["unknown"] == 0
    report = (tmp_path / "audit" / "report.html").read_text()
    assert "<h4>examples.lift_box:LiftBox</h4>" in report and "held up" in report
    assert "delivered" not in report.split("How far trials got")[1].split("</table>")[0]
    out = tmp_path / "lerobot"
    assert main(["export", "--format", "lerobot", "--store", str(store), "--out", str(out)]) == 0
    info = json.loads((out / "meta" / "info.json").read_text())
    names = info["features"]["observation.environment_state"]["names"]
    assert "lift_m" in names and names[-1].startswith("box")  # no goal point to relate
    tasks = (out / "meta" / "tasks.parquet").read_bytes()
    assert b"Lift the box off the conveyor and hold it up." in tasks

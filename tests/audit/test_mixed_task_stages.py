"""A store of several tasks: the summary's top-level stage counts name each task's stages,
and a trial counts as having reached a stage only in its own task's order (a box transfer
trial that delivered did not reach palletize's ``placed_1``; a palletize trial that
placed two boxes did reach ``grasped``)."""

from __future__ import annotations

import json
import sqlite3
from pathlib import Path

import pytest

from workcell.cli.main import main

STAGES = [("box_transfer", "delivered"), ("palletize", "placed_2"), ("palletize", "grasped")]
"""Each collected trial's task and stage, as the store is made to say."""


def test_a_mixed_store_counts_each_trial_in_its_own_tasks_stages(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    store = tmp_path / "s.sqlite"
    argv = ["collect", "--writer", "inline", "--store", str(store), "--mode", "collection"]
    assert main([*argv, "--trials", "3", "--set", "task.time_limit_s=0.5", "--json"]) == 0
    with sqlite3.connect(store) as connection:
        ids = [row[0] for row in connection.execute("SELECT trial_id FROM trials ORDER BY rowid")]
        for trial_id, (task, stage) in zip(ids, STAGES, strict=True):
            connection.execute(
                "UPDATE trials SET task = ?, stage = ? WHERE trial_id = ?", (task, stage, trial_id)
            )
    assert main(["audit", "--store", str(store), "--out", str(tmp_path / "a")]) == 0
    capsys.readouterr()
    stages = json.loads((tmp_path / "a" / "summary.json").read_text())["task_stages"]
    assert list(stages["by_task"]) == ["box_transfer", "palletize"]
    ended, reached = stages["ended_at"], stages["reached"]
    assert list(ended) == [
        *("none", "touched", "grasped", "lifted", "over_zone", "delivered"),
        *("placed_1", "placed_2", "placed_3", "placed_4", "settled"),
    ]
    assert {s: n for s, n in ended.items() if n} == {"delivered": 1, "placed_2": 1, "grasped": 1}
    assert reached["none"] == reached["touched"] == reached["grasped"] == 3
    assert reached["lifted"] == reached["over_zone"] == reached["delivered"] == 1  # box transfer
    assert reached["placed_1"] == reached["placed_2"] == 1  # palletize's one, not the delivery
    assert reached["placed_3"] == reached["settled"] == 0

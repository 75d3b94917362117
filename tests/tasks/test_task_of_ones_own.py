"""A task of one's own (``module:Class``) goes the whole way: collected by name, recorded
with its name, selected by it and exported with its own instruction."""

from __future__ import annotations

import json
import sqlite3
from pathlib import Path

import pyarrow.parquet as pq  # type: ignore[import-untyped, unused-ignore]
import pytest

from workcell.cli.main import main

CAREFUL = "tests.tasks.external_task:CarefulTransfer"
ONE_BOX = "Carry the box from the conveyor to the delivery table."
POLITE = "Please carry 1 box(es) to the table, gently."


def _instructions(out: Path) -> list[str]:
    tasks: list[str] = pq.read_table(out / "meta/tasks.parquet").to_pydict()["task"]
    return tasks


def test_a_task_of_ones_own_is_collected_recorded_and_exported_with_its_instruction(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    store = tmp_path / "s.sqlite"
    collect = ["collect", "--mode", "collection", "--trials", "2", "--store", str(store)]
    assert main([*collect, "--task", CAREFUL, "--seed", "3", "--operator-id", "careful"]) == 0
    assert main([*collect, "--seed", "4"]) == 0
    with sqlite3.connect(store) as connection:
        rows = connection.execute("SELECT operator_id, parameters_json FROM sessions").fetchall()
        outcomes = {o for (o,) in connection.execute("SELECT outcome FROM trials")}
    kinds = {operator: json.loads(text)["task"]["kind"] for operator, text in rows}
    assert kinds == {"careful": CAREFUL, "expert": "box_transfer"}
    assert outcomes == {"success"}  # its judge is box transfer's
    export = ["export", "--format", "lerobot", "--store", str(store), "--out"]
    capsys.readouterr()
    assert main([*export, str(tmp_path / "all")]) == 0
    assert sorted(_instructions(tmp_path / "all")) == [ONE_BOX, POLITE]
    assert main([*export, str(tmp_path / "careful"), "--task", CAREFUL]) == 0
    assert _instructions(tmp_path / "careful") == [POLITE]
    assert "left out 2: 2 another task (--task)" in capsys.readouterr().out
    assert main([*export, str(tmp_path / "expert"), "--operator", "expert"]) == 0
    assert _instructions(tmp_path / "expert") == [ONE_BOX]
    assert "left out 2: 2 another operator (--operator)" in capsys.readouterr().out
    refused = ["export", "--format", "csv", "--store", str(store), "--task", CAREFUL]
    assert main([*refused, "--out", str(tmp_path / "csv")]) == 2
    assert "--task: applies to the lerobot, hdf5 and rerun formats" in capsys.readouterr().err

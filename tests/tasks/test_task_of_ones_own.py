"""A task of one's own (``module:Class``) goes the whole way: collected by name, recorded
with its name, and exported with its own instruction."""

from __future__ import annotations

import json
import sqlite3
from pathlib import Path

import pyarrow.parquet as pq  # type: ignore[import-untyped, unused-ignore]

from workcell.cli.main import main

CAREFUL = "tests.tasks.external_task:CarefulTransfer"


def test_a_task_of_ones_own_is_collected_recorded_and_exported_with_its_instruction(
    tmp_path: Path,
) -> None:
    store, out = tmp_path / "s.sqlite", tmp_path / "lerobot"
    argv = ["collect", "--task", CAREFUL, "--mode", "collection", "--trials", "2"]
    assert main([*argv, "--seed", "3", "--store", str(store)]) == 0
    with sqlite3.connect(store) as connection:
        (parameters,) = connection.execute("SELECT parameters_json FROM sessions").fetchone()
        outcomes = [o for (o,) in connection.execute("SELECT outcome FROM trials")]
    assert json.loads(parameters)["task"]["kind"] == CAREFUL
    assert outcomes == ["success", "success"]  # its judge is box transfer's
    assert main(["export", "--format", "lerobot", "--store", str(store), "--out", str(out)]) == 0
    tasks = pq.read_table(out / "meta/tasks.parquet").to_pydict()
    assert tasks["task"] == ["Please carry 1 box(es) to the table, gently."]

"""A study piloted headless with four participants (the expert at four skills, each
running their plan of a practice and a collection session in each of two conditions, in
the Latin square's orders). Every output a researcher analyses names each trial's
participant, condition and study step: the audit's trials.csv and report, the LeRobot
provenance, the HDF5 demos (whose file-level ``env_args`` claims no one session's
settings), the Rerun recordings and the Sessions page's data. ``workcell audit --study``
compares the conditions within participants (tests/study/test_study_analysis.py)."""

from __future__ import annotations

import csv
import json
from pathlib import Path
from typing import Any

import h5py  # type: ignore[import-untyped, unused-ignore]
import pyarrow.parquet as pq  # type: ignore[import-untyped, unused-ignore]

from tests.export.test_rerun import read_recording
from tests.server.harness import running_server
from tests.study.conftest import TRIALS, Expected
from workcell.audit.trials_csv import COLUMNS
from workcell.cli.main import main
from workcell.export.hdf5_export import HDF5_NAME


def _tags(record: dict[str, Any]) -> tuple[str, str, int]:
    return (record["operator_id"], record["condition"], record["study_step"])


def test_the_audit_names_each_trials_participant_condition_and_step(
    study_store: tuple[Path, Expected], tmp_path: Path
) -> None:
    store, expected = study_store
    assert main(["audit", "--store", str(store), "--out", str(tmp_path / "audit")]) == 0
    with (tmp_path / "audit" / "trials.csv").open(newline="") as file:
        rows = list(csv.DictReader(file))
    assert tuple(rows[0]) == COLUMNS
    assert COLUMNS[-3:] == ("operator_id", "condition", "study_step")  # added at the end
    assert len(rows) == TRIALS
    for row in rows:
        operator, condition, step = expected[row["session_id"]]
        assert (row["operator_id"], row["condition"], row["study_step"]) == (
            operator,
            condition,
            str(step),
        )
    report = (tmp_path / "audit" / "report.html").read_text()
    assert "<th>participant</th><th>condition</th><th>study step</th>" in report


def test_the_dataset_exports_name_each_episodes_participant_condition_and_step(
    study_store: tuple[Path, Expected], tmp_path: Path
) -> None:
    store, expected = study_store
    for format_ in ("lerobot", "hdf5", "rerun"):
        out = str(tmp_path / format_)
        assert main(["export", "--format", format_, "--store", str(store), "--out", out]) == 0

    rows = pq.read_table(tmp_path / "lerobot" / "meta/workcell_provenance.parquet").to_pylist()
    assert len(rows) == TRIALS
    assert all(_tags(row) == expected[row["session_id"]] for row in rows)
    document = json.loads((tmp_path / "lerobot" / "meta/workcell_provenance.json").read_text())
    assert {k: _tags(v) for k, v in document["sessions"].items()} == expected
    assert all(_tags(e) == expected[e["session_id"]] for e in document["episodes"])

    with h5py.File(tmp_path / "hdf5" / HDF5_NAME, "r") as file:
        data = file["data"]
        shared = json.loads(data.attrs["env_args"])["env_kwargs"]["session_parameters"]
        differ = json.loads(data.attrs["env_args_differ"])
        grasps = set()
        assert len(data) == TRIALS
        for name in data:
            attrs = data[name].attrs
            tags = (attrs["operator_id"], attrs["condition"], int(attrs["study_step"]))
            assert tags == expected[attrs["session_id"]]
            own = json.loads(attrs["env_args"])["env_kwargs"]["session_parameters"]
            assert own["condition"] == attrs["condition"]
            grasps.add((attrs["condition"], own["world"]["grasp"]))
    assert grasps == {("assisted", "assisted"), ("physical", "physical")}
    # the file claims no one session's settings: what differs is named, not guessed
    assert {"condition", "world.grasp", "operator_id", "study_step", "seed"} <= set(differ)
    assert "grasp" not in shared["world"] and "condition" not in shared
    assert shared["recording"]["sampling_rate_hz"] == 20

    recordings = sorted((tmp_path / "rerun").glob("*.rrd"))
    assert len(recordings) == TRIALS
    for path in recordings:
        recording = read_recording(path)
        fields = recording.static_fields("/")
        (session_id,) = fields["session_id"]
        operator, condition, step = expected[session_id]
        assert (fields["operator_id"], fields["condition"], fields["study_step"]) == (
            [operator],
            [condition],
            [step],
        )
        (text,) = recording.static_value("provenance", "TextDocument:text")
        assert f"operator {operator}, condition {condition}, study step {step}" in text


def test_the_sessions_page_data_names_each_sessions_participant_condition_and_step(
    study_store: tuple[Path, Expected], tmp_path: Path
) -> None:
    store, expected = study_store
    (tmp_path / "store.sqlite").write_bytes(store.read_bytes())
    with running_server(tmp_path) as server:
        sessions = server.get_json("/api/sessions")["sessions"]
    assert len(sessions) == len(expected) == 16
    assert all(_tags(s) == expected[s["session_id"]] for s in sessions)

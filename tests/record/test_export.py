"""CSV export: the contract's columns, exact round trip, manifest, and tamper evidence."""

from __future__ import annotations

import csv
import json
import sqlite3
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from numpy.typing import NDArray

from tests.record import synthetic
from workcell.audit.csv_source import CsvSource
from workcell.record import ExportError, Store
from workcell.record.batch import RowBatch
from workcell.record.columns import (
    EVENT_COLUMNS,
    FILTERED_POSE_COLUMNS,
    FRAME_COLUMNS,
    FRAME_CONTRACT_COLUMNS,
    FRAME_TASK_COLUMNS,
    SESSION_COLUMNS,
    TRIAL_COLUMNS,
    TRIAL_TASK_COLUMNS,
)
from workcell.record.csv_format import FILES, file_sha256
from workcell.record.export_csv import columns_equal, export_csv, read_csv_export
from workcell.record.layout import TableLayout
from workcell.record.schema import SCHEMA_VERSION, column_list
from workcell.record.verify import verify_export
from workcell.sim.joints import JOINT_ORDER


@pytest.fixture
def exported(tmp_path: Path) -> tuple[Path, Path]:
    store = tmp_path / "s.db"
    synthetic.fill_store(store)
    out = tmp_path / "csv"
    export_csv(store, out)
    return store, out


def _header(path: Path) -> list[str]:
    with path.open(newline="") as file:
        return next(csv.reader(file))


def test_files_have_exactly_the_contract_columns(exported: tuple[Path, Path]) -> None:
    _, out = exported
    assert sorted(p.name for p in out.iterdir()) == sorted([*FILES, "manifest.json"])
    assert _header(out / "frames.csv") == list(FRAME_COLUMNS)
    assert _header(out / "frames.csv")[: len(FRAME_CONTRACT_COLUMNS)] == list(
        FRAME_CONTRACT_COLUMNS
    )
    assert _header(out / "trials.csv") == [*TRIAL_COLUMNS, *TRIAL_TASK_COLUMNS, "driver"]
    assert _header(out / "frames.csv")[-3:] == [*FRAME_TASK_COLUMNS, "intervention"]
    assert _header(out / "sessions.csv") == list(SESSION_COLUMNS)
    assert _header(out / "events.csv") == list(EVENT_COLUMNS)
    assert verify_export(out) == []


def test_round_trip_is_exact(exported: tuple[Path, Path]) -> None:
    store, out = exported
    back = read_csv_export(out)
    conn = sqlite3.connect(store)
    for name, layout in FILES.items():
        sql = f"SELECT {column_list(layout.grouped)} FROM {layout.name}"
        rows = conn.execute(sql).fetchall()
        from_store = RowBatch.from_grouped(layout, rows).to_columns()
        from_csv = back.tables[name]
        assert tuple(from_csv) == layout.names
        order, reference = _order(layout, from_csv), _order(layout, from_store)
        for column in layout.names:
            a, b = from_csv[column][order], from_store[column][reference]
            assert columns_equal(a, b), (name, column)
    with Store.open(store, writer=False) as reader:
        for trial in reader.trials():
            frames = reader.frames(trial.trial_id)
            mine = back.tables["frames.csv"]["trial_id"] == trial.trial_id
            for column in FRAME_COLUMNS:
                assert columns_equal(back.tables["frames.csv"][column][mine], frames[column])


def test_manifest_records_parameters_and_checksums(exported: tuple[Path, Path]) -> None:
    store, out = exported
    manifest = json.loads((out / "manifest.json").read_text())
    assert manifest["schema_version"] == SCHEMA_VERSION and manifest["joint_order"] == list(
        JOINT_ORDER
    )
    with Store.open(store, writer=False) as reader:
        sessions = reader.sessions()
        n_frames = reader.counts().frames
    for session in sessions:
        entry = manifest["sessions"][session.session_id]
        assert entry["parameters"] == session.parameters
        assert entry["thresholds"] == session.thresholds
        assert entry["metric_definitions"] == session.metric_definitions
    assert manifest["files"]["frames.csv"]["rows"] == n_frames
    assert all(len(f["sha256"]) == 64 for f in manifest["files"].values())
    assert manifest["columns"]["trials.csv"] == [*TRIAL_COLUMNS, *TRIAL_TASK_COLUMNS, "driver"]


@pytest.mark.parametrize("name", ["frames.csv", "trials.csv", "sessions.csv"])
def test_one_flipped_byte_is_named(exported: tuple[Path, Path], name: str) -> None:
    _, out = exported
    path = out / name
    data = bytearray(path.read_bytes())
    data[len(data) // 2] ^= 0x01
    path.write_bytes(bytes(data))
    findings = verify_export(out)
    assert findings and {f.table for f in findings} == {name}
    assert any("sha256" in f.problem and "changed after export" in f.problem for f in findings)
    assert str(findings[0]).startswith(f"{out}: {name}: ")


def test_extra_and_missing_files_are_named(exported: tuple[Path, Path]) -> None:
    _, out = exported
    (out / "events.csv").unlink()
    (out / "notes.txt").write_text("mine")
    found = {(f.table, f.problem.split(":")[0]) for f in verify_export(out)}
    assert found == {
        ("events.csv", "listed in manifest.json but missing"),
        ("notes.txt", "not listed in manifest.json"),
    }


def test_export_refuses_a_non_empty_directory(exported: tuple[Path, Path]) -> None:
    store, out = exported
    with pytest.raises(ExportError, match="not an empty directory"):
        export_csv(store, out)


def _order(layout: TableLayout, columns: dict[str, NDArray[Any]]) -> NDArray[np.intp]:
    """Row order by the table's key (e.g. trial_id then frame_index)."""
    keys = [
        np.asarray(columns[k]).astype(str if columns[k].dtype == object else None)
        for k in reversed(layout.key)
    ]
    return np.lexsort(keys)


def test_an_export_made_before_the_filtered_poses_still_reads(exported: tuple[Path, Path]) -> None:
    """A version-2 export's frames.csv has no filtered-pose columns: it reads, with those
    columns NULL, and verifies against its own manifest (whose sha256 is rewritten here as
    version 2 wrote it for that file)."""
    store, out = exported
    frames = out / "frames.csv"
    with frames.open(newline="") as file:
        rows = list(csv.reader(file))
    keep = len(FRAME_COLUMNS) - len(FILTERED_POSE_COLUMNS) - len(FRAME_TASK_COLUMNS) - 1
    assert rows[0][keep:] == [*FILTERED_POSE_COLUMNS, *FRAME_TASK_COLUMNS, "intervention"]
    with frames.open("w", newline="") as file:
        csv.writer(file).writerows(row[:keep] for row in rows)
    _cut(out, "trials.csv", len(TRIAL_COLUMNS))
    manifest = json.loads((out / "manifest.json").read_text())
    manifest["files"]["frames.csv"]["sha256"] = file_sha256(frames)
    (out / "manifest.json").write_text(json.dumps(manifest))
    assert verify_export(out) == []
    back = read_csv_export(out).tables["frames.csv"]
    assert all(np.isnan(back[name]).all() for name in FILTERED_POSE_COLUMNS)
    assert all(value is None for value in back["stage"])
    with Store.open(store, writer=False) as reader:
        trial = reader.trials()[0]
        recorded = reader.frames(trial.trial_id)
    mine = back["trial_id"] == trial.trial_id
    for column in FRAME_COLUMNS[:keep]:
        assert columns_equal(back[column][mine], recorded[column]), column
    source = CsvSource(out)
    try:
        assert trial.trial_id in dict(source.frames())
    finally:
        source.close()
    with frames.open("w", newline="") as file:  # any other header is still refused
        csv.writer(file).writerows(row[: keep - 1] for row in rows)
    with pytest.raises(ExportError, match="header is not the contract's columns"):
        read_csv_export(out)


def test_an_export_made_before_the_driver_columns_still_reads(
    exported: tuple[Path, Path],
) -> None:
    """A version-5 export has no driver in trials.csv and no intervention in frames.csv: it
    reads, with those columns NULL; this version's export holds them as recorded."""
    _, out = exported
    whole = read_csv_export(out).tables
    assert set(whole["trials.csv"]["driver"]) == {"expert"}
    assert set(whole["frames.csv"]["intervention"].tolist()) == {0.0, 1.0}
    _cut(out, "trials.csv", len(TRIAL_COLUMNS) + len(TRIAL_TASK_COLUMNS))
    _cut(out, "frames.csv", len(FRAME_COLUMNS) - 1)
    assert verify_export(out) == []
    back = read_csv_export(out).tables
    assert all(value is None for value in back["trials.csv"]["driver"])
    assert np.isnan(back["frames.csv"]["intervention"]).all()
    assert back["trials.csv"]["task"].tolist() == whole["trials.csv"]["task"].tolist()
    assert columns_equal(back["frames.csv"]["progress"], whole["frames.csv"]["progress"])


def _cut(out: Path, name: str, keep: int) -> None:
    """Keep the first ``keep`` columns of the export's file ``name`` (as an older version
    wrote it), its sha256 in the manifest rewritten to fit."""
    path = out / name
    with path.open(newline="") as file:
        rows = list(csv.reader(file))
    with path.open("w", newline="") as file:
        csv.writer(file, lineterminator="\n").writerows(row[:keep] for row in rows)
    manifest = json.loads((out / "manifest.json").read_text())
    manifest["files"][name]["sha256"] = file_sha256(path)
    (out / "manifest.json").write_text(json.dumps(manifest))


def test_an_export_made_before_the_task_columns_still_reads(exported: tuple[Path, Path]) -> None:
    """A version-4 export has no task columns in trials.csv and frames.csv: it reads, with
    those columns NULL, and verifies against its own manifest; this version's export holds
    them."""
    store, out = exported
    whole = read_csv_export(out).tables
    with Store.open(store, writer=False) as reader:
        trials = {t.trial_id: t for t in reader.trials()}
    for i, trial_id in enumerate(whole["trials.csv"]["trial_id"]):
        trial = trials[trial_id]
        assert whole["trials.csv"]["task"][i] == trial.task == "box_transfer"
        assert whole["trials.csv"]["stage"][i] == trial.stage
        assert json.loads(whole["trials.csv"]["goal_json"][i]) == trial.goal
    assert set(whole["frames.csv"]["stage"]) == set(synthetic.STAGES)
    _cut(out, "trials.csv", len(TRIAL_COLUMNS))
    _cut(out, "frames.csv", len(FRAME_COLUMNS) - len(FRAME_TASK_COLUMNS) - 1)
    assert verify_export(out) == []
    back = read_csv_export(out).tables
    assert all(value is None for value in back["trials.csv"]["task"])
    assert np.isnan(back["frames.csv"]["progress"]).all()
    for column in FRAME_COLUMNS[: -len(FRAME_TASK_COLUMNS) - 1]:
        assert columns_equal(back["frames.csv"][column], whole["frames.csv"][column]), column

"""Sources: the store and a CSV export give the same rows and frames."""

from __future__ import annotations

import dataclasses
import sqlite3
from pathlib import Path

import numpy as np
import pytest

from tests.audit import synthetic
from workcell.audit.csv_source import CsvSource
from workcell.audit.errors import AuditError
from workcell.audit.parallel import shares, worker_count
from workcell.audit.run import run_audit
from workcell.audit.source import FRAME_COLUMNS_READ
from workcell.audit.store_source import StoreSource
from workcell.metrics import FrameArrays
from workcell.record.export_csv import export_csv


def test_frame_arrays_match_frame_arrays_from_columns() -> None:
    matrix = np.random.default_rng(0).normal(size=(25, len(FRAME_COLUMNS_READ)))
    ours = FrameArrays.from_matrix(matrix)
    theirs = FrameArrays.from_columns({n: matrix[:, i] for i, n in enumerate(FRAME_COLUMNS_READ)})
    for field in dataclasses.fields(FrameArrays):
        assert np.array_equal(getattr(ours, field.name), getattr(theirs, field.name))


def test_store_and_export_read_alike(tmp_path: Path) -> None:
    store = tmp_path / "s.sqlite"
    ids = synthetic.fill(store, ["success", "timeout", "interrupted"], n_frames=25)
    export_csv(store, tmp_path / "csv")
    a, b = StoreSource(store), CsvSource(tmp_path / "csv")
    try:
        assert a.sessions() == b.sessions()
        assert a.trials() == b.trials()
        assert a.annotations() == b.annotations()
        frames_a, frames_b = dict(a.frames()), dict(b.frames())
        assert list(frames_a) == list(frames_b) == ids
        for trial_id in ids:
            for field in dataclasses.fields(FrameArrays):
                x = getattr(frames_a[trial_id], field.name)
                y = getattr(frames_b[trial_id], field.name)
                assert np.array_equal(x, y, equal_nan=True)
        mid_a, mid_b = a.midpoints(ids[:2]), b.midpoints(ids[:2])
        assert set(mid_a) == set(mid_b) == set(ids[:2])
        assert all(np.array_equal(mid_a[i], mid_b[i]) for i in ids[:2])
    finally:
        a.close()
        b.close()


def test_an_export_whose_trials_are_interleaved_is_refused(tmp_path: Path) -> None:
    store = tmp_path / "s.sqlite"
    synthetic.fill(store, ["success", "success"], n_frames=5)
    export_csv(store, tmp_path / "csv")
    frames = tmp_path / "csv" / "frames.csv"
    lines = frames.read_text().splitlines(keepends=True)
    frames.write_text("".join([lines[0], lines[6], *lines[1:6], *lines[7:]]))
    with pytest.raises(AuditError, match="are not together"):
        dict(CsvSource(tmp_path / "csv").frames())


def test_a_folder_that_is_not_an_export_is_refused(tmp_path: Path) -> None:
    with pytest.raises(AuditError, match=r"holds no manifest\.json"):
        CsvSource(tmp_path)


def test_frame_blocks_rows_and_workers_give_the_same_audit(tmp_path: Path) -> None:
    store = tmp_path / "s.sqlite"
    ids = synthetic.fill(store, ["success", "timeout", "success", "interrupted"] * 3)
    with sqlite3.connect(store) as conn:  # one trial as from a store before frame blocks
        conn.execute("DELETE FROM frame_blocks WHERE trial_id = ?", (ids[1],))
    audits = []
    for use_blocks, workers in ((True, 1), (False, 1), (True, 3)):
        source = StoreSource(store, use_blocks=use_blocks)
        try:
            audits.append(run_audit(source, workers=workers))
            if workers == 1:
                assert source.read_from_blocks == (len(ids) - 1 if use_blocks else 0)
        finally:
            source.close()
    blocks, rows, parallel = audits
    assert blocks.trials == rows.trials == parallel.trials
    assert blocks.findings == rows.findings == parallel.findings
    assert blocks.frames_read == rows.frames_read == parallel.frames_read == 40 * len(ids)
    assert list(blocks.trajectories) == list(rows.trajectories)
    for trial_id, path in blocks.trajectories.items():
        assert np.array_equal(path, rows.trajectories[trial_id])


def test_a_block_that_disagrees_with_its_trial_row_is_not_read(tmp_path: Path) -> None:
    store = tmp_path / "s.sqlite"
    ids = synthetic.fill(store, ["success", "success"], n_frames=30)
    with sqlite3.connect(store) as conn:  # a block of other frames than the trial's
        conn.execute("UPDATE frame_blocks SET n_frames = 29 WHERE trial_id = ?", (ids[0],))
    source = StoreSource(store)
    try:
        frames = dict(source.frames())
        assert source.read_from_blocks == 1
        assert len(frames[ids[0]]) == 30  # read from the rows
    finally:
        source.close()


def test_parallel_shares_cover_every_trial_in_order() -> None:
    rows = [f"t{i}" for i in range(10)]
    sizes = [5, 100, 1, 1, 1, 50, 50, 0, 3, 9]
    cut = shares(rows, sizes, 4)
    assert [r for share in cut for r in share] == rows
    assert 2 <= len(cut) <= 4
    assert worker_count(3, 10) == 3 and worker_count(None, 10) == 1

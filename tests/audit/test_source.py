"""Sources: the store and a CSV export give the same rows and frames."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest

from tests.audit import synthetic
from workcell.audit.csv_source import CsvSource
from workcell.audit.errors import AuditError
from workcell.audit.source import FRAME_COLUMNS_READ, frame_arrays
from workcell.audit.store_source import StoreSource
from workcell.metrics import FrameArrays
from workcell.record.export_csv import export_csv


def test_frame_arrays_match_frame_arrays_from_columns() -> None:
    matrix = np.random.default_rng(0).normal(size=(25, len(FRAME_COLUMNS_READ)))
    ours = frame_arrays(matrix)
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

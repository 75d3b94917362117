"""Bad input to dataset exports: one clear line on stderr and exit status 2."""

from __future__ import annotations

import os
import sqlite3
from pathlib import Path

import pytest

from tests.export.stores import Stores, collect, record_interrupted
from workcell.cli.main import EXIT_USAGE, main
from workcell.record.store import Store


@pytest.fixture(autouse=True)
def _keep_mujoco_gl(monkeypatch: pytest.MonkeyPatch) -> None:
    """Keep MUJOCO_GL as the other tests expect it, whatever this test does to it."""
    monkeypatch.setenv("MUJOCO_GL", os.environ.get("MUJOCO_GL", "egl"))


def _fails(argv: list[str], capsys: pytest.CaptureFixture[str]) -> str:
    """Run ``workcell export``; it must fail with one line, which is returned."""
    assert main(["export", *argv]) == EXIT_USAGE
    captured = capsys.readouterr()
    lines = captured.err.splitlines()
    assert len(lines) == 1, captured.err
    assert lines[0].startswith("workcell: error: ")
    return lines[0]


def _copy(source: Path, target: Path) -> Path:
    with sqlite3.connect(source) as src, sqlite3.connect(target) as dst:
        src.backup(dst)
    return target


@pytest.mark.parametrize("fmt", ["lerobot", "hdf5"])
def test_empty_store(fmt: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    store = tmp_path / "empty.sqlite"
    Store.open(store, writer=True).close()
    line = _fails(["--format", fmt, "--store", str(store), "--out", str(tmp_path / "o")], capsys)
    assert "holds no trials" in line
    assert not (tmp_path / "o").exists()


def test_store_failing_verify(
    recorded: Stores, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    store = _copy(recorded.short, tmp_path / "changed.sqlite")
    with sqlite3.connect(store) as conn:
        conn.execute("UPDATE frames SET base_x = base_x + 1 WHERE frame_index = 2")
    argv = ["--format", "lerobot", "--store", str(store), "--out", str(tmp_path / "o")]
    line = _fails(argv, capsys)
    assert "fails verification (" in line and "first: checksum mismatch" in line
    assert f"run 'workcell verify --store {store}'" in line
    assert not (tmp_path / "o").exists()


def test_non_empty_output(
    recorded: Stores, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    (tmp_path / "keep.txt").write_text("mine")
    line = _fails(
        ["--format", "hdf5", "--store", str(recorded.short), "--out", str(tmp_path)], capsys
    )
    assert line.endswith("is not an empty folder; give a new or empty folder")
    assert [p.name for p in tmp_path.iterdir()] == ["keep.txt"]


def test_nothing_included_points_at_all(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    store = tmp_path / "quit.sqlite"
    record_interrupted(store, seed=4)
    argv = ["--format", "lerobot", "--store", str(store), "--out", str(tmp_path / "o")]
    line = _fails(argv, capsys)
    assert (
        "none of its 1 closed trials can be exported "
        "(left out: 1 incomplete: interrupted (application_quit))" in line
    )
    assert line.endswith("pass --all to export trials that are not included")
    argv[-1] = str(tmp_path / "all")
    assert main(["export", *argv, "--all"]) == 0
    assert "exported 1 episode," in capsys.readouterr().out


def test_sessions_of_different_rates(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    store = tmp_path / "rates.sqlite"
    collect(store, "--trials", "1", "--set", "task.time_limit_s=0.5")
    rate = ["--set", "recording.sampling_rate_hz=10"]
    collect(store, "--trials", "1", "--set", "task.time_limit_s=0.5", *rate)
    capsys.readouterr()
    argv = ["--format", "hdf5", "--store", str(store), "--out", str(tmp_path / "o")]
    line = _fails(argv, capsys)
    assert "the selected sessions differ in frame rate" in line
    assert "export them separately" in line


def test_options_that_do_not_apply(
    recorded: Stores, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    base = ["--store", str(recorded.short), "--out", str(tmp_path / "o")]
    line = _fails(["--format", "csv", "--cameras", "head_cam", *base], capsys)
    assert line.endswith("--cameras: applies to the lerobot and hdf5 formats")
    line = _fails(["--format", "lerobot", "--size", "64x48", *base], capsys)
    assert line.endswith("--size applies to camera images: give --cameras too")
    line = _fails(["--format", "lerobot", "--cameras", "tail_cam", *base], capsys)
    assert "name one or more of head_cam, wrist_l_cam, wrist_r_cam" in line
    line = _fails(["--format", "rerun", "--cameras", "head_cam", *base], capsys)
    assert line.endswith("--cameras: applies to the lerobot and hdf5 formats")
    assert not (tmp_path / "o").exists()

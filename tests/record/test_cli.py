"""``workcell verify`` and ``workcell export``, run through their own parsers."""

from __future__ import annotations

import argparse
import sqlite3
from collections.abc import Sequence
from pathlib import Path

import pytest

from tests.record import synthetic
from workcell.cli import export, verify
from workcell.errors import ConfigError
from workcell.record import Store, StoreError


def _run(argv: Sequence[str]) -> int:
    parser = argparse.ArgumentParser(prog="workcell")
    subparsers = parser.add_subparsers(dest="command", required=True)
    verify.register(subparsers)
    export.register(subparsers)
    args = parser.parse_args(argv)
    status: int = args.func(args)
    return status


@pytest.fixture
def store(tmp_path: Path) -> Path:
    path = tmp_path / "s.db"
    synthetic.fill_store(path)
    return path


def test_verify_a_good_store(store: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert _run(["verify", "--store", str(store)]) == 0
    assert capsys.readouterr().out == (
        "ok: 2 sessions, 4 trials, 38 frames; hash chains of 2 sessions (8 links, unsigned) "
        "verified\n"
    )


def test_verify_names_each_problem(store: Path, capsys: pytest.CaptureFixture[str]) -> None:
    conn = sqlite3.connect(store)
    conn.execute("UPDATE frames SET base_x = base_x + 1 WHERE frame_index = 2")
    conn.commit()
    conn.close()
    assert _run(["verify", "--store", str(store)]) == verify.EXIT_PROBLEMS
    lines = capsys.readouterr().out.splitlines()
    assert len(lines) == 4  # one frame in each of four trials
    assert all(line.startswith(f"{store}: frames trial ") for line in lines)
    assert all(
        line.endswith("frame 2: checksum mismatch: the frame was changed after it was written")
        for line in lines
    )


def test_export_then_verify_the_export(
    store: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "out"
    assert _run(["export", "--format", "csv", "--store", str(store), "--out", str(out)]) == 0
    assert capsys.readouterr().out == f"exported 2 sessions, 4 trials, 38 frames to {out}\n"
    assert _run(["verify", "--csv", str(out)]) == 0
    assert capsys.readouterr().out == "ok: 2 sessions, 4 trials, 38 frames verified\n"
    with (out / "trials.csv").open("a") as file:
        file.write("\n")
    assert _run(["verify", "--csv", str(out)]) == 1
    lines = capsys.readouterr().out.splitlines()
    assert lines[0].startswith(f"{out}: trials.csv: sha256 ")
    assert lines[1:] == [f"{out}: trials.csv: 5 rows, the manifest says 4"]


def test_unavailable_and_unknown_formats(store: Path, tmp_path: Path) -> None:
    argv = ["--store", str(store), "--out", str(tmp_path / "out")]
    formats = "csv, lerobot, hdf5, rerun"  # rerun is available now
    with pytest.raises(ConfigError, match=rf"--format 'parquet': must be one of {formats}$"):
        _run(["export", "--format", "parquet", *argv])
    with pytest.raises(ConfigError, match="must be one of csv"):
        _run(["export", "--format", "xlsx", *argv])
    assert not (tmp_path / "out").exists()


def test_verify_recover_closes_an_orphan_trial(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path = tmp_path / "s.db"
    store = Store.open(path, writer=True)
    trial_id = store.start_trial(
        store.create_session(synthetic.session_info()), synthetic.trial_start()
    )
    store.close()
    assert _run(["verify", "--store", str(path)]) == 1
    assert "--recover" in capsys.readouterr().out
    assert _run(["verify", "--recover", "--store", str(path)]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out == [
        f"recovered: trial {trial_id} closed as interrupted (crash_recovered)",
        "ok: 1 sessions, 1 trials, 0 frames; hash chains of 1 sessions (3 links, unsigned) "
        "verified",
    ]


def test_verify_a_missing_store_is_one_clear_error(tmp_path: Path) -> None:
    with pytest.raises(StoreError, match="no store at"):
        _run(["verify", "--store", str(tmp_path / "nothing.db")])

"""A damaged store file (random bytes over some of its pages, or cut short) is refused by
every command with one line, never read as valid and never recorded into."""

from __future__ import annotations

import os
import random
from pathlib import Path

import pytest

from tests.record import synthetic
from tests.server.harness import running_server
from workcell.cli.main import main
from workcell.record import Store
from workcell.record.errors import StoreError

PAGE = 4096


def damaged_store(path: Path) -> Path:
    """A store of synthetic.fill_store's sessions with every seventh page overwritten."""
    synthetic.fill_store(path)
    pages = path.stat().st_size // PAGE
    noise = random.Random(1)
    with path.open("r+b") as file:
        for page in range(3, pages, 7):
            file.seek(page * PAGE)
            file.write(noise.randbytes(PAGE))
    return path


def one_error_line(capsys: pytest.CaptureFixture[str]) -> str:
    captured = capsys.readouterr()
    (line,) = captured.err.splitlines()
    assert "Traceback" not in captured.out + captured.err
    return line


def test_every_command_refuses_a_damaged_store_in_one_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    store = damaged_store(tmp_path / "s.db")
    good = tmp_path / "good.db"
    synthetic.fill_store(good)
    before = store.read_bytes()

    assert main(["verify", "--store", str(store)]) == 1
    (line,) = capsys.readouterr().out.splitlines()
    assert f"{store}: database: the file is damaged (SQLite's integrity check:" in line

    for argv in (
        ["audit", "--store", str(store), "--out", str(tmp_path / "audit")],
        ["export", "--format", "csv", "--store", str(store), "--out", str(tmp_path / "csv")],
        ["merge", "--out", str(tmp_path / "merged.db"), str(store)],
        ["merge", "--out", str(store), str(good)],
        ["verify", "--recover", "--store", str(store)],
        [
            "annotate",
            "--store",
            str(store),
            "--trial",
            "t",
            "--exclude",
            "--reason",
            "x",
            "--by",
            "me",
        ],
        ["serve", "--store", str(store), "--port", "0"],
        ["collect", "--trials", "1", "--store", str(store)],
    ):
        assert main(argv) == 2, argv
        line = one_error_line(capsys)
        assert line.startswith(f"workcell: error: store {store} is damaged"), (argv, line)
    with pytest.raises(StoreError, match="is damaged"):
        Store.open(store, writer=True)  # what a live session's store writer opens
    assert store.read_bytes() == before  # nothing was written into it
    assert not (tmp_path / "csv").exists()


def test_the_sessions_api_names_a_store_cut_short(tmp_path: Path) -> None:
    with running_server(tmp_path) as server:
        store = server.options.store
        synthetic.fill_store(store)
        os.truncate(store, store.stat().st_size // 2)
        status, body = server.get("/api/sessions")
    assert status == 503, body
    assert f"store {store} is damaged" in body.decode()

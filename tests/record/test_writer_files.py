"""The files a writer keeps beside its store, ``<store>.lock`` and ``<store>.reserve``:
there while it writes, gone after a clean close, kept for the next writer when it leaves
something open; and never two writers at once though the lock file comes and goes."""

from __future__ import annotations

import threading
import time
from pathlib import Path

import pytest

from tests.audit import synthetic
from workcell.cli.main import main
from workcell.record import Store
from workcell.record.connection import WriterLock, lock_path, writer_active
from workcell.record.errors import StoreError
from workcell.record.reserve import RESERVE_BYTES, reserve_path
from workcell.record.verify import verify_store


def test_a_clean_collect_leaves_only_the_store(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    store = tmp_path / "s.sqlite"
    argv = ["collect", "--trials", "1", "--set", "task.time_limit_s=0.5", "--store", str(store)]
    assert main(argv) == 0
    assert main([*argv, "--writer", "inline", "--seed", "3"]) == 0
    capsys.readouterr()
    assert [p.name for p in tmp_path.iterdir()] == ["s.sqlite"]
    assert verify_store(store) == []
    with Store.open(store, writer=False) as reader:
        assert [s.status for s in reader.sessions()] == ["completed", "completed"]


def test_a_clean_collect_by_workers_leaves_only_the_store(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """Its shards merged and the result verified (by a reader), nothing else stays."""
    store = tmp_path / "s.sqlite"
    argv = ["collect", "--trials", "2", "--workers", "2", "--set", "task.time_limit_s=0.3"]
    assert main([*argv, "--store", str(store)]) == 0
    assert "verified" in capsys.readouterr().out
    assert [p.name for p in tmp_path.iterdir()] == ["s.sqlite"]


def test_a_reader_leaves_sqlites_empty_files_which_the_next_clean_writer_removes(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """What the README says of ``<store>-wal`` and ``<store>-shm``."""
    store = tmp_path / "s.sqlite"
    argv = ["collect", "--trials", "1", "--set", "task.time_limit_s=0.5", "--store", str(store)]
    assert main(argv) == 0
    assert main(["verify", "--store", str(store)]) == 0
    capsys.readouterr()
    beside = {p.name: p.stat().st_size for p in tmp_path.iterdir()}
    assert beside.keys() == {"s.sqlite", "s.sqlite-wal", "s.sqlite-shm"}
    assert beside["s.sqlite-wal"] == 0
    assert main([*argv, "--seed", "1"]) == 0
    capsys.readouterr()
    assert [p.name for p in tmp_path.iterdir()] == ["s.sqlite"]


def test_the_files_are_there_while_writing_and_kept_for_what_is_left_open(
    tmp_path: Path,
) -> None:
    path = tmp_path / "s.db"
    with Store.open(path, writer=True) as store:
        assert reserve_path(path).stat().st_size == RESERVE_BYTES
        assert lock_path(path).is_file() and writer_active(path)
        store.create_session(synthetic.session_info())  # left running
    assert not lock_path(path).exists() and not writer_active(path)
    assert reserve_path(path).stat().st_size == RESERVE_BYTES  # room to recover it in
    with Store.open(path, writer=True) as store:
        assert len(store.recovered) == 0  # a session without trials: closed, no trial
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s.db"]


def test_a_writer_waiting_while_the_writer_closes_excludes_the_next(tmp_path: Path) -> None:
    """The waiting writer locked a lock file that its closing holder removed; it must not
    write beside a third writer that made a new one."""
    path = tmp_path / "s.db"
    first = WriterLock(path)
    opened: list[WriterLock] = []
    errors: list[BaseException] = []

    def second() -> None:
        try:
            opened.append(WriterLock(path))
        except BaseException as error:
            errors.append(error)

    waiting = threading.Thread(target=second)
    waiting.start()
    time.sleep(0.3)  # the second writer is retrying the lock (it tries for 2 s)
    first.release()
    waiting.join()
    assert errors == [] and len(opened) == 1
    assert writer_active(path)
    with pytest.raises(StoreError, match="already open for writing"):
        Store.open(path, writer=True)
    opened[0].release()
    with Store.open(path, writer=True):
        assert writer_active(path)

"""A full disk (a real tmpfs that fills up, and a file-size limit) stops recording with one
clear message, marks the trial storage_error, closes the session and leaves every earlier
trial intact."""

from __future__ import annotations

import contextlib
import json
import resource
import signal
import sqlite3
from pathlib import Path

import numpy as np
import pytest

from tests.record import synthetic
from tests.record.processes import collect, finish, start_writer
from tests.record.small_disk import fill, small_disk
from tests.record.writer_process import EXIT_STORAGE_ERROR
from workcell.cli.main import main
from workcell.record import Store
from workcell.record.errors import StorageError
from workcell.record.export_csv import columns_equal
from workcell.record.reserve import RESERVE_BYTES, reserve_path
from workcell.record.verify import verify_store

FILE_SIZE_LIMIT = 1 << 20
"""Bytes any one file of the writer may reach: the WAL fills it within a few hundred
frames."""
COMPLETE, COMPLETE_FRAMES = 2, 40


def _limit_file_size() -> None:
    """In the child: a 1 MiB file-size limit, and writes past it fail (EFBIG) instead of
    killing the process with SIGXFSZ."""
    signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
    resource.setrlimit(resource.RLIMIT_FSIZE, (FILE_SIZE_LIMIT, FILE_SIZE_LIMIT))


def test_disk_full_gives_storage_error_and_keeps_earlier_trials(tmp_path: Path) -> None:
    path = tmp_path / "s.db"
    process = start_writer(
        path,
        "--complete",
        str(COMPLETE),
        "--complete-frames",
        str(COMPLETE_FRAMES),
        preexec_fn=_limit_file_size,
    )
    last, err = finish(process)
    assert process.returncode == EXIT_STORAGE_ERROR, err
    (message,) = err.splitlines()  # one clear line
    assert message.startswith(f"store {path}: could not write (")
    assert "recording stopped" in message and "file-size limit" in message
    assert message.endswith("everything committed before is intact")
    assert last > 0

    with Store.open(path, writer=True) as store:
        assert store.recovered == ()  # the writer closed its trial itself
        trials = store.trials()
        assert [t.outcome for t in trials] == ["success"] * COMPLETE + ["interrupted"]
        failed = trials[-1]
        assert failed.interruption_reason == "storage_error"
        assert failed.n_frames is not None and failed.n_frames >= last
        (event,) = store.events(failed.trial_id)
        assert event.kind == "interruption" and event.payload["error"] == message
        assert store.sessions()[0].status == "interrupted"
        for k, trial in enumerate(trials[:COMPLETE]):
            assert trial.n_frames == COMPLETE_FRAMES
            frames = store.frames(trial.trial_id)
            for name, values in synthetic.frames(0, COMPLETE_FRAMES, seed=k).items():
                assert columns_equal(frames[name], np.asarray(values, frames[name].dtype))
    assert verify_store(path) == []


MIB = 1 << 20


def _errors(err: str) -> list[str]:
    return [line for line in err.splitlines() if line.startswith("workcell: error: ")]


def test_collect_on_a_disk_that_fills_up(tmp_path: Path) -> None:
    """``workcell collect`` on a 4 MiB tmpfs: the trial that hits the full disk ends
    interrupted (storage_error), the session is closed, the store verifies, every message
    names the full disk; a new or reopened store is refused cleanly while the disk is full
    and opens again once there is room."""
    with small_disk(tmp_path / "disk", 4 * MIB) as disk:
        ballast = disk / "ballast"
        ballast.write_bytes(b"\0" * MIB)  # to free later
        store = disk / "s.sqlite"
        out, err = collect(store, "--mode", "collection").communicate(timeout=600)
        (error,) = _errors(err)
        assert "Traceback" not in err
        assert f"the disk holding {disk} is full" in error
        rows = [json.loads(line) for line in out.splitlines()]
        assert rows[0]["outcome"] == "success"
        assert (rows[-1]["outcome"], rows[-1]["interruption_reason"]) == (
            "interrupted",
            "storage_error",
        )
        assert verify_store(store) == []  # nothing left open: no recovery needed
        with Store.open(store, writer=False) as reader:
            (session,) = reader.sessions()
            trials = reader.trials()
            events = [e for e in reader.events() if e.kind == "interruption"]
        assert session.status == "interrupted"
        assert [(t.outcome, t.interruption_reason) for t in trials] == [
            (r["outcome"], r["interruption_reason"]) for r in rows
        ]
        (event,) = events
        assert event.payload["error"] == error.removeprefix("workcell: error: ")
        assert not reserve_path(store).exists()  # its room went into closing the trial

        # the disk is full now: a new store is refused before anything is written
        process = collect(disk / "new.sqlite", "--trials", "1")
        _, err = process.communicate(timeout=120)
        assert process.returncode == 2
        (error,) = _errors(err)
        assert "Traceback" not in err and f"the disk holding {disk} is full" in error
        assert "nothing was recorded" in error
        assert not (disk / "new.sqlite").exists()
        # reopening the store is refused the same way, and changes nothing
        process = collect(store, "--trials", "1")
        _, err = process.communicate(timeout=120)
        assert process.returncode == 2 and len(_errors(err)) == 1, err
        assert "is full" in err and "rollback" not in err and "Traceback" not in err
        assert verify_store(store) == []

        ballast.unlink()  # room again: the store opens for writing
        with Store.open(store, writer=True):
            assert reserve_path(store).stat().st_size == RESERVE_BYTES
        assert not reserve_path(store).exists()  # a clean close removes it
        assert main(["verify", "--recover", "--store", str(store)]) == 0


def test_a_trial_whose_start_meets_the_full_disk_is_stored_interrupted(tmp_path: Path) -> None:
    """The disk fills while a trial's first rows are being written: the failed transaction
    takes the trial's row with it, yet the trial the operator was told of is stored,
    ``interrupted``/``storage_error``, after the trial that ended before it."""
    with small_disk(tmp_path / "disk", 4 * MIB) as disk:
        path = disk / "s.db"
        with Store.open(path, writer=True) as store:
            session = store.create_session(synthetic.session_info())
            first = store.start_trial(session, synthetic.trial_start())
            store.add_frames(first, synthetic.batch(store, first, synthetic.frames(0, 40)))
            store.end_trial(first, synthetic.trial_end(40))
            store.commit()
            fill(disk, leave_bytes=0)
            with pytest.raises(StorageError, match="full"):
                trial = store.start_trial(session, synthetic.trial_start(1))
                for start in range(0, 2400, 100):  # more than the log has room for
                    frames = synthetic.frames(start, 100, seed=1)
                    store.add_frames(trial, synthetic.batch(store, trial, frames))
                store.commit()
            assert store.try_interrupt_session(session, "storage_error")
        with Store.open(path, writer=False) as reader:
            trials = reader.trials()
            (event,) = [e for e in reader.events() if e.kind == "interruption"]
            assert reader.sessions()[0].status == "interrupted"
        assert [(t.outcome, t.interruption_reason) for t in trials] == [
            ("success", None),
            ("interrupted", "storage_error"),
        ]
        assert [t.trial_index for t in trials] == [0, 1]
        assert trials[1].n_frames == 0 and event.trial_id == trials[1].trial_id
        assert verify_store(path) == []


@pytest.mark.parametrize("n_frames", [20, 2400])
def test_closing_a_trial_fits_in_the_headroom_many_times(tmp_path: Path, n_frames: int) -> None:
    """What closing a trial and its session appends to the log, against the headroom
    file's size: it must fit several times over (RESERVE_BYTES says eight)."""
    path = tmp_path / "s.db"
    with Store.open(path, writer=True) as store:
        session = store.create_session(synthetic.session_info())
        trial = store.start_trial(session, synthetic.trial_start())
        for start in range(0, n_frames, 100):
            store.add_frames(
                trial,
                synthetic.batch(store, trial, synthetic.frames(start, min(100, n_frames - start))),
            )
            store.commit()
        wal = path.with_name(path.name + "-wal")
        with contextlib.closing(sqlite3.connect(path)) as other:  # the log starts empty
            other.execute("PRAGMA wal_checkpoint(TRUNCATE)")
        assert wal.stat().st_size == 0
        assert store.try_interrupt_session(session, "storage_error")
        appended = wal.stat().st_size
    assert 0 < appended * 4 <= RESERVE_BYTES, appended

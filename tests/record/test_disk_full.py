"""A full disk (here: a file-size limit) stops recording with one clear message, marks the
trial storage_error and leaves every earlier trial intact."""

from __future__ import annotations

import resource
import signal
from pathlib import Path

import numpy as np

from tests.record import synthetic
from tests.record.processes import finish, start_writer
from tests.record.writer_process import EXIT_STORAGE_ERROR
from workcell.record import Store
from workcell.record.export_csv import columns_equal
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

"""A trial's end is durable against a power cut: its commit syncs the write-ahead log
(``synchronous=FULL``), while frame batches do not (``NORMAL``: the cost stays off the
20 Hz path). Watched with strace: which system calls reach the disk, and when."""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]

SCRIPT = textwrap.dedent(
    """
    import os, sys
    from tests.record import synthetic
    from workcell.record import Store

    def mark(name):  # a system call strace shows, between the steps
        os.path.exists("/workcell-mark-" + name)

    with Store.open(sys.argv[1], writer=True) as store:
        session = store.create_session(synthetic.session_info())
        trial = store.start_trial(session, synthetic.trial_start())
        mark("frames")
        for start in range(0, 20, 5):
            store.add_frames(trial, synthetic.batch(store, trial, synthetic.frames(start, 5)))
            store.commit()
        mark("end_trial")
        store.end_trial(trial, synthetic.trial_end(20))
        mark("end_session")
        store.end_session(session)
        mark("done")
    """
)


def _strace() -> str:
    found = shutil.which("strace")
    if found is None:
        if os.environ.get("CI"):
            pytest.fail("strace is missing: .ci/run installs it")
        pytest.skip("strace is not installed (.ci/run installs it)")
    return found


def _syncs_by_step(store: Path, tmp_path: Path) -> dict[str, list[str]]:
    """The files each step synced (fsync/fdatasync), by the step's mark."""
    log = tmp_path / "strace.log"
    subprocess.run(
        [
            _strace(),
            "-f",
            "-y",  # file descriptors with their paths
            "-e",
            "trace=fsync,fdatasync,newfstatat,stat",
            "-o",
            str(log),
            sys.executable,
            "-c",
            SCRIPT,
            str(store),
        ],
        cwd=REPO,
        check=True,
        capture_output=True,
    )
    steps: dict[str, list[str]] = {}
    current = "open"
    for line in log.read_text().splitlines():
        mark = re.search(r'"/workcell-mark-(\w+)"', line)
        if mark:
            current = mark.group(1)
            continue
        sync = re.search(r"f(?:data)?sync\(\d+<([^>]*)>\)", line)
        if sync:
            steps.setdefault(current, []).append(Path(sync.group(1)).name)
    return steps


def test_trial_and_session_ends_sync_the_log_and_frame_batches_do_not(tmp_path: Path) -> None:
    store = tmp_path / "s.db"
    steps = _syncs_by_step(store, tmp_path)
    wal = f"{store.name}-wal"
    assert steps.get("frames", []) == []  # four frame batches committed, nothing synced
    assert wal in steps.get("end_trial", [])  # the trial's end is on the disk when it returns
    assert wal in steps.get("end_session", [])

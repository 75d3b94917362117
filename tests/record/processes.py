"""Real child processes of the record tests: ``workcell collect``, and ``writer_process``
(and reading what they printed and recorded)."""

from __future__ import annotations

import os
import subprocess
import sys
import time
from collections.abc import Callable
from pathlib import Path

from workcell.record import Store

REPO = Path(__file__).resolve().parents[2]
TIMEOUT_S = 30.0


def start_writer(
    store: Path, *args: str, preexec_fn: Callable[[], None] | None = None
) -> subprocess.Popen[str]:
    """Start ``python -m tests.record.writer_process --store STORE ARGS...``."""
    return subprocess.Popen(
        [sys.executable, "-m", "tests.record.writer_process", "--store", str(store), *args],
        cwd=REPO,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        preexec_fn=preexec_fn,  # noqa: PLW1509 (only given where no other thread runs)
    )


def next_count(process: subprocess.Popen[str]) -> int:
    """The next committed frame count the writer printed (waits for it)."""
    assert process.stdout is not None
    line = process.stdout.readline()
    if not line:
        _, err = process.communicate(timeout=TIMEOUT_S)
        raise AssertionError(f"writer ended before printing a count: {err}")
    return int(line)


def finish(process: subprocess.Popen[str], last_seen: int = 0) -> tuple[int, str]:
    """Wait for the writer to end; the last count it printed (``last_seen`` if it printed
    none since) and its stderr. Reads through the same buffered stream as
    :func:`next_count` (``communicate`` would skip what that stream had read ahead)."""
    assert process.stdout is not None and process.stderr is not None
    out = process.stdout.read()  # to the end: the writer exits after its trial
    err = process.stderr.read()
    process.wait(timeout=TIMEOUT_S)
    counts = [int(line) for line in out.split()]
    return (counts[-1] if counts else last_seen), err


def collect(
    store: Path, *args: str, preexec_fn: Callable[[], None] | None = None
) -> subprocess.Popen[str]:
    return subprocess.Popen(
        [sys.executable, "-m", "workcell", "collect", "--store", str(store), "--json", *args],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env={**os.environ, "PYTHONUNBUFFERED": "1"},
        preexec_fn=preexec_fn,  # noqa: PLW1509 (no threads in the test process)
    )


def committed_frames(store: Path) -> int:
    """Frames a reader sees right now (what the recorder has committed)."""
    if not store.exists():
        return 0
    try:
        with Store.open(store, writer=False) as reader:
            return reader.counts().frames
    except Exception:  # the recorder may not have created the schema yet
        return 0


def wait_for_recording(store: Path, timeout_s: float = 120.0) -> None:
    """Until the recorder has committed frames (however loaded the machine is)."""
    deadline = time.monotonic() + timeout_s
    while committed_frames(store) == 0:
        assert time.monotonic() < deadline, f"{store} never received a frame"
        time.sleep(0.05)


def wait_for_trials(store: Path, count: int, timeout_s: float = 120.0) -> None:
    """Until the recorder has started ``count`` trials."""
    deadline = time.monotonic() + timeout_s
    while True:
        with Store.open(store, writer=False) as reader:
            if reader.counts().trials >= count:
                return
        assert time.monotonic() < deadline, f"{store} never had {count} trials"
        time.sleep(0.02)


def writer_of(pid: int, timeout_s: float = 30.0) -> int:
    """The pid of the store writer process (``workcell.recording.store_worker``) that the
    process ``pid`` started, or that one of its descendants started (a server's session
    process)."""
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        parents: dict[int, int] = {}
        writers: list[int] = []
        for entry in Path("/proc").iterdir():
            if not entry.name.isdigit():
                continue
            try:
                parent = int((entry / "stat").read_text().rsplit(")", 1)[1].split()[1])
                command = (entry / "cmdline").read_bytes()
            except (OSError, IndexError, ValueError):
                continue
            parents[int(entry.name)] = parent
            if b"workcell.recording.store_worker" in command:
                writers.append(int(entry.name))
        for writer in writers:
            ancestor = parents.get(writer)
            while ancestor is not None and ancestor != pid:
                ancestor = parents.get(ancestor)
            if ancestor == pid:
                return writer
        time.sleep(0.02)
    raise AssertionError(f"process {pid} has no store writer process")


def leader_status(pid: int) -> tuple[str, int] | None:
    """The state letter (``R``, ``S``, ``Z``...) of process ``pid``'s leading thread and how
    many threads the process still has, both from one read of ``/proc/PID/status`` (the
    kernel fills it in one pass), or None once the process is gone. Walking
    ``/proc/PID/task`` instead can skip a live thread while others end (the listing is
    indexed by position), so it cannot tell that every thread has exited."""
    try:
        status = Path(f"/proc/{pid}/status").read_text()
    except (FileNotFoundError, ProcessLookupError):
        return None
    fields = dict(line.split(":", 1) for line in status.splitlines() if ":" in line)
    return fields["State"].split()[0], int(fields["Threads"])


def wait_until_dead(pid: int, timeout_s: float = TIMEOUT_S) -> None:
    """Until the child ``pid`` has exited, every thread of it (a zombie its parent has not
    reaped yet, or gone): only then does ``waitpid`` report it. A SIGKILL takes effect some
    time after ``os.kill`` returns, longer on a busy machine. Does not reap it. The leader
    of a killed process is a zombie while its other threads are still ending; the count of
    threads reaches 1 as the last of them is released, the moment ``waitpid`` may report
    the process."""
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        status = leader_status(pid)
        if status is None:
            return
        state, threads = status
        if state in ("Z", "X") and threads <= 1:
            return
        time.sleep(0.005)
    raise AssertionError(f"process {pid} did not die within {timeout_s} s")

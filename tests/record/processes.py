"""Running ``writer_process`` as a real child process and reading what it printed."""

from __future__ import annotations

import subprocess
import sys
from collections.abc import Callable
from pathlib import Path

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
    none since) and its stderr."""
    out, err = process.communicate(timeout=TIMEOUT_S)
    counts = [int(line) for line in out.split()]
    return (counts[-1] if counts else last_seen), err

"""What ``workcell train`` leaves in its output directory ``OUT`` beside LeRobot's
checkpoints: the log, ``OUT/train.log``, and only the newest of the periodic checkpoints.

LeRobot refuses an output directory that exists when it starts, so ``OUT`` can be made
only once LeRobot has checked it: its first log line (``INFO 2026-12-01 10:00:00 ...``)
comes after that check. Until then the log is held in memory; from then on it is
written to ``OUT/train.log`` as it comes. A run that ends before (a bad option) makes
``OUT`` with the log alone, which the next run with the same ``--out`` replaces.
"""

from __future__ import annotations

import contextlib
import re
import shutil
from pathlib import Path
from typing import TextIO

LOG_FILE = "train.log"
CHECKPOINTS = "checkpoints"
LAST = "last"
_LEROBOT_LOG_LINE = re.compile(r"^(DEBUG|INFO|WARNING|ERROR|CRITICAL) \d{4}-\d\d-\d\d ")
"""LeRobot's own log format (``init_logging``), which it sets up after checking OUT."""


def only_a_log(out: Path) -> bool:
    """Whether ``out`` holds nothing but a log that a run which never started training
    left there."""
    return out.is_dir() and [p.name for p in out.iterdir()] == [LOG_FILE]


class TrainingLog:
    """``OUT/train.log``, opened as soon as LeRobot has checked ``OUT``."""

    def __init__(self, out: Path) -> None:
        self.path = out / LOG_FILE
        self._held: list[str] = []
        self._file: TextIO | None = None

    def write(self, line: str) -> None:
        if self._file is None and _LEROBOT_LOG_LINE.match(line):
            self.open()
        if self._file is None:
            self._held.append(line)
            return
        self._file.write(line)
        self._file.flush()

    def open(self) -> None:
        """Make ``OUT`` and write what was held (at once, if not done yet)."""
        if self._file is not None:
            return
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self._file = self.path.open("w")
        self._file.writelines(self._held)
        self._file.flush()
        self._held = []

    def close(self) -> None:
        self.open()
        assert self._file is not None
        self._file.close()


def remove_older_checkpoints(out: Path) -> None:
    """Delete the step checkpoints older than the one ``OUT/checkpoints/last`` points to.
    Safe while LeRobot trains: it writes only newer ones, and moves ``last`` to a
    checkpoint once that is whole."""
    folder = out / CHECKPOINTS
    last = folder / LAST
    if not last.is_symlink():
        return  # none yet, or LeRobot is moving it
    with contextlib.suppress(OSError):
        newest = last.readlink().name
        if not newest.isdigit():
            return
        for step in folder.iterdir():
            if step.name.isdigit() and int(step.name) < int(newest) and not step.is_symlink():
                shutil.rmtree(step, ignore_errors=True)

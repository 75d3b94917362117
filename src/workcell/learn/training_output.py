"""What ``workcell train`` leaves in its output directory ``OUT`` beside LeRobot's
checkpoints: the log, ``OUT/train.log``, and only the newest of the periodic checkpoints.

``OUT`` and its log are made as the training process starts, and the process's whole
output is written there as it comes (LeRobot runs through
:mod:`workcell.learn.lerobot_child`, which lets it write into an ``OUT`` that holds only
the log). A run that fails before training leaves ``OUT`` with the log alone, which the
next run with the same ``--out`` replaces.
"""

from __future__ import annotations

import contextlib
import shutil
from pathlib import Path
from typing import TextIO

LOG_FILE = "train.log"
CHECKPOINTS = "checkpoints"
LAST = "last"


def only_a_log(out: Path) -> bool:
    """Whether ``out`` holds nothing but a log that a run which never started training
    left there (or the log of the run starting now)."""
    return out.is_dir() and [p.name for p in out.iterdir()] == [LOG_FILE]


class TrainingLog:
    """``OUT/train.log``, made (with ``OUT``) at once, written line by line."""

    def __init__(self, out: Path) -> None:
        self.path = out / LOG_FILE
        out.mkdir(parents=True, exist_ok=True)
        self._file: TextIO = self.path.open("w")

    def write(self, line: str) -> None:
        self._file.write(line)
        self._file.flush()

    def close(self) -> None:
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

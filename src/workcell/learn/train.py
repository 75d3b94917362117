"""``workcell train``: LeRobot's own training (``lerobot-train``) on a Workcell export.

The training runs in a child process, ``python -m lerobot.scripts.lerobot_train`` with the
arguments of :mod:`workcell.learn.train_options`, offline (nothing is downloaded or
uploaded). Its whole output goes to ``OUT/train.log``; what it reports is turned into one
progress line (step, loss, speed, time left). The result is LeRobot's standard checkpoint,
``OUT/checkpoints/last/pretrained_model``, which ``lerobot`` loads and ``workcell collect
--operator policy:OUT`` drives with.
"""

from __future__ import annotations

import json
import os
import re
import shlex
import subprocess
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from workcell.learn.checkpoint import LAST_CHECKPOINT, PolicyCheckpoint
from workcell.learn.errors import LearnError, MissingLearnExtraError
from workcell.learn.train_options import TrainOptions, lerobot_arguments

LOG_FILE = "train.log"
TRAIN_MODULE = "lerobot.scripts.lerobot_train"
OFFLINE_ENVIRONMENT = {
    "HF_HUB_OFFLINE": "1",
    "HF_DATASETS_OFFLINE": "1",
    "WANDB_MODE": "disabled",
    "TOKENIZERS_PARALLELISM": "false",
}
_LOG_LINE = re.compile(r"step:(?P<step>\S+).*?loss:(?P<loss>[-+0-9.eE]+)")
_BAR = re.compile(r"\|\s*(?P<step>\d+)/(?P<steps>\d+) \[")
"""tqdm's progress bar: ``Training:  12%|#  | 1234/10000 [00:10<01:00, 3.1step/s]``."""
_BIG_NUMBER = {"K": 1e3, "M": 1e6, "B": 1e9, "T": 1e12}


@dataclass(frozen=True)
class TrainProgress:
    step: int
    steps: int
    loss: float
    elapsed_s: float
    """Seconds since the training started (the process, data and model set-up included)."""
    steps_per_s: float
    """Since the first step (set-up excluded); 0 until two steps were reported."""

    @property
    def remaining_s(self) -> float | None:
        rate = self.steps_per_s
        return (self.steps - self.step) / rate if rate > 0 else None


class ProgressReader:
    """Turns LeRobot's training log lines into :class:`TrainProgress` reports."""

    def __init__(self, steps: int) -> None:
        self.steps = steps
        self._bar_step = 0
        self._first: tuple[int, float] | None = None

    def read(self, line: str, elapsed_s: float) -> TrainProgress | None:
        """The report in ``line`` (None for every other line). The step comes from
        tqdm's bar where it shows (LeRobot's log rounds it: ``1K``), the loss from the log."""
        bar = _BAR.search(line)
        if bar is not None:
            self._bar_step = int(bar["step"])
        match = _LOG_LINE.search(line)
        if match is None:
            return None
        try:
            step, loss = max(self._bar_step, _number(match["step"])), float(match["loss"])
        except ValueError:
            return None
        if self._first is None:
            self._first = (step, elapsed_s)
        first_step, first_s = self._first
        rate = (step - first_step) / (elapsed_s - first_s) if elapsed_s > first_s else 0.0
        return TrainProgress(step, self.steps, loss, elapsed_s, rate)


@dataclass(frozen=True)
class TrainResult:
    checkpoint: PolicyCheckpoint
    seconds: float
    last: TrainProgress | None
    command: list[str]


def check_dataset(dataset: Path) -> bool:
    """Refuse a directory that is not a LeRobotDataset v3.0; whether it has videos."""
    info_path = dataset / "meta" / "info.json"
    try:
        info = json.loads(info_path.read_text())
    except (OSError, ValueError):
        raise LearnError(
            f"--dataset {str(dataset)!r}: no LeRobotDataset there (meta/info.json missing or "
            "unreadable); make one with workcell export --format lerobot"
        ) from None
    if info.get("codebase_version") != "v3.0":
        raise LearnError(
            f"--dataset {str(dataset)!r}: LeRobot dataset version "
            f"{info.get('codebase_version')!r}; LeRobot 0.4 trains on v3.0"
        )
    features = info.get("features", {})
    return any(f.get("dtype") == "video" for f in features.values())


def train_command(options: TrainOptions) -> tuple[list[str], str]:
    """The child process's command line, and the device it trains on."""
    has_videos = check_dataset(options.dataset)
    if options.out.exists() and (not options.out.is_dir() or any(options.out.iterdir())):
        raise LearnError(
            f"--out {str(options.out)!r} exists and is not empty; LeRobot writes a new "
            "training there: give a new directory"
        )
    device = options.device if options.device != "auto" else _best_device()
    command = [sys.executable, "-m", TRAIN_MODULE, *lerobot_arguments(options, device, has_videos)]
    return command, device


def run_training(
    options: TrainOptions, on_progress: Callable[[TrainProgress], None] | None = None
) -> TrainResult:
    """Train, reporting each of LeRobot's log lines; the checkpoint it wrote."""
    command, _ = train_command(options)
    if options.out.exists():
        options.out.rmdir()  # empty: LeRobot refuses an existing output directory
    log_path = options.out.parent / f".{options.out.name}.{LOG_FILE}"
    started = time.monotonic()
    last: TrainProgress | None = None
    reader = ProgressReader(options.steps)
    environment = {**os.environ, **OFFLINE_ENVIRONMENT}
    if options.threads is not None:
        environment["OMP_NUM_THREADS"] = environment["MKL_NUM_THREADS"] = str(options.threads)
    with log_path.open("w") as log:
        log.write(f"$ {shlex.join(command)}\n")
        log.flush()
        process = subprocess.Popen(
            command,
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            text=True,
            env=environment,
        )
        assert process.stdout is not None
        try:
            for line in process.stdout:
                log.write(line)
                log.flush()
                progress = reader.read(line, time.monotonic() - started)
                if progress is not None:
                    last = progress
                    if on_progress is not None:
                        on_progress(progress)
        except BaseException:
            process.kill()
            process.wait()
            raise
        code = process.wait()
    final_log = options.out / LOG_FILE
    if options.out.is_dir():
        log_path.replace(final_log)
    else:
        final_log = log_path
    if code != 0:
        raise LearnError(
            f"LeRobot's training failed (exit {code}): {_last_error(final_log)}; "
            f"the whole log is in {final_log}"
        )
    checkpoint = PolicyCheckpoint.locate(options.out / LAST_CHECKPOINT)
    return TrainResult(checkpoint, time.monotonic() - started, last, command)


def _number(text: str) -> int:
    """LeRobot's ``format_big_number``: ``1K`` is 1000."""
    if text and text[-1] in _BIG_NUMBER:
        return round(float(text[:-1]) * _BIG_NUMBER[text[-1]])
    return int(float(text))


def _last_error(log_path: Path) -> str:
    lines = [line.strip() for line in log_path.read_text(errors="replace").splitlines()]
    errors = [line for line in lines if "Error" in line or "error" in line]
    return (errors or lines or ["no output"])[-1][:400]


def _best_device() -> str:
    try:
        import torch  # noqa: PLC0415
    except ImportError:
        raise MissingLearnExtraError("torch") from None
    return "cuda" if torch.cuda.is_available() else "cpu"

"""``workcell train``: LeRobot's own training (``lerobot-train``) on a Workcell export.

The training runs in a child process, LeRobot's own ``lerobot-train`` (through
:mod:`workcell.learn.lerobot_child`, so that its log is in ``OUT`` from the start) with the
arguments of :mod:`workcell.learn.train_options`, offline (nothing is downloaded or
uploaded), on :data:`~workcell.learn.train_options.DEFAULT_THREADS` torch thread unless
told otherwise. Its whole output goes to ``OUT/train.log`` from the moment it starts
(:mod:`workcell.learn.training_output`); what it reports is turned into one progress line
(step, loss, speed, time left). The result is LeRobot's standard checkpoint,
``OUT/checkpoints/last/pretrained_model``, which ``lerobot`` loads and ``workcell collect
--operator policy:OUT`` drives with; by default it is saved every tenth of the run, so a
run cut short leaves the newest one there.
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
from workcell.learn.training_output import TrainingLog, only_a_log, remove_older_checkpoints

TRAIN_MODULE = "workcell.learn.lerobot_child"
"""``lerobot-train`` whose log can be in OUT before LeRobot checks OUT."""
OFFLINE_ENVIRONMENT = {
    "HF_HUB_OFFLINE": "1",
    "HF_DATASETS_OFFLINE": "1",
    "WANDB_MODE": "disabled",
    "TOKENIZERS_PARALLELISM": "false",
}
_LOG_LINE = re.compile(r"step:(?P<step>\S+).*?loss:(?P<loss>[-+0-9.eE]+)")
"""LeRobot's log line, ``step:2K smpl:48K ep:90 epch:1.02 loss:0.512 ...``: its step is
rounded (``2K`` at step 1500), its loss the mean since the line before."""
_CHECKPOINT_LINE = "Checkpoint policy after step"


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

    def __init__(self, steps: int, log_every: int) -> None:
        self.steps = steps
        self.log_every = log_every
        """LeRobot logs after every ``log_every``-th step (``--log_freq``) of a new run."""
        self._lines = 0
        self._first: tuple[int, float] | None = None

    def read(self, line: str, elapsed_s: float) -> TrainProgress | None:
        """The report in ``line`` (None for every other line). Its step is the true one:
        the n-th log line comes after step n x ``log_every`` (the line's own step is
        rounded); its loss is the line's; its rate is since the first report."""
        match = _LOG_LINE.search(line)
        if match is None:
            return None
        try:
            loss = float(match["loss"])
        except ValueError:
            return None
        self._lines += 1
        step = min(self.steps, self._lines * self.log_every)
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
    out = options.out
    if out.exists() and (not out.is_dir() or (any(out.iterdir()) and not only_a_log(out))):
        raise LearnError(
            f"--out {str(out)!r} exists and is not empty; LeRobot writes a new "
            "training there: give a new directory"
        )
    device = options.device if options.device != "auto" else _best_device()
    command = [sys.executable, "-m", TRAIN_MODULE, *lerobot_arguments(options, device, has_videos)]
    return command, device


def thread_environment(options: TrainOptions) -> dict[str, str]:
    """The variables that set the training process's torch threads (none for torch's own
    default)."""
    if not options.threads:
        return {}
    threads = str(options.threads)
    return {"OMP_NUM_THREADS": threads, "MKL_NUM_THREADS": threads}


def run_training(
    options: TrainOptions, on_progress: Callable[[TrainProgress], None] | None = None
) -> TrainResult:
    """Train, reporting each of LeRobot's log lines; the checkpoint it wrote."""
    command, _ = train_command(options)
    log = TrainingLog(options.out)  # replaces the log of a run that never started
    started = time.monotonic()
    last: TrainProgress | None = None
    reader = ProgressReader(options.steps, options.log_every)
    threads = thread_environment(options)
    environment = {**os.environ, **OFFLINE_ENVIRONMENT, **threads}
    variables = [f"{key}={value}" for key, value in threads.items()]
    log.write(f"$ {shlex.join([*variables, *command])}\n")
    try:
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
                if _CHECKPOINT_LINE in line and options.save_every is None:
                    remove_older_checkpoints(options.out)
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
    finally:
        log.close()
    if code != 0:
        raise LearnError(
            f"LeRobot's training failed (exit {code}): {_last_error(log.path)}; "
            f"the whole log is in {log.path}"
        )
    if options.save_every is None:
        remove_older_checkpoints(options.out)
    checkpoint = PolicyCheckpoint.locate(options.out / LAST_CHECKPOINT)
    return TrainResult(checkpoint, time.monotonic() - started, last, command)


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

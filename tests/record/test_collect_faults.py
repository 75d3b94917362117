"""Recording a real ``workcell collect`` process: kills, signals, a full disk, the clock.

Real SQLite, real processes, real signals, the real simulation and expert.
"""

from __future__ import annotations

import json
import os
import random
import resource
import signal
import subprocess
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest

from tests.record.processes import (
    collect,
    committed_frames,
    wait_for_recording,
    wait_for_trials,
    writer_of,
)
from workcell.metrics import FrameArrays, compute_trial_metrics
from workcell.record import Store
from workcell.record.columns import FRAME_COLUMNS, FRAME_DEVICE_COLUMNS
from workcell.record.verify import verify_store
from workcell.recording.recorder import metric_thresholds
from workcell.session.config import SessionConfig

KILLS = 20
PARALLEL = 4


def _kill_each_after_its_delay(
    runs: list[tuple[Path, subprocess.Popen[str], float]], timeout_s: float = 120.0
) -> dict[Path, int]:
    """SIGKILL each run's process ``delay`` s after its store first showed committed frames
    (the runs' delays overlap in time); the frames each store had committed just before."""
    recording_since: dict[Path, float] = {}
    seen: dict[Path, int] = {}
    deadline = time.monotonic() + timeout_s
    while len(seen) < len(runs):
        for store, process, delay in runs:
            now = time.monotonic()
            if store in seen:
                continue
            if store not in recording_since:
                assert now < deadline, f"{store} never received a frame"
                if committed_frames(store) > 0:
                    recording_since[store] = now
            elif now >= recording_since[store] + delay:
                seen[store] = committed_frames(store)
                process.send_signal(signal.SIGKILL)
                process.wait(timeout=30)
        time.sleep(0.02)
    return seen


@pytest.mark.slow
def test_sigkill_at_random_moments_loses_nothing_committed(tmp_path: Path) -> None:
    rng = random.Random(20261121)
    # A random moment after recording has begun: within a trial, between two commits, in
    # a countdown or between trials, whatever the process is doing then.
    delays = [rng.uniform(0.0, 3.0) for _ in range(KILLS)]
    hit_a_running_trial = 0
    for wave in range(0, KILLS, PARALLEL):
        runs = []
        for k in range(wave, wave + PARALLEL):
            store = tmp_path / f"kill{k}.sqlite"
            runs.append((store, collect(store, "--mode", "collection"), delays[k]))
        seen = _kill_each_after_its_delay(runs)
        for store, _, delay in runs:
            with Store.open(store, writer=True) as writer:  # the next open recovers
                recovered = writer.recovered
                trials = writer.trials()
                frames_total = writer.counts().frames
            assert verify_store(store) == [], f"kill after {delay:.2f} s"
            assert frames_total >= seen[store], f"kill after {delay:.2f} s"
            orphans = [t for t in trials if t.interruption_reason == "crash_recovered"]
            assert len(orphans) == len(recovered) <= 1, trials
            # A kill during a countdown leaves no trial open; otherwise the last one is.
            finished = trials[:-1] if orphans else trials
            assert all(t.outcome == "success" for t in finished)
            if not orphans:
                continue
            hit_a_running_trial += 1
            assert orphans[0].trial_id == trials[-1].trial_id
            with Store.open(store, writer=False) as reader:
                frames = reader.frames(orphans[0].trial_id)
            t_sim = frames["t_sim"]
            # every committed frame is there, in order, on the 20 Hz grid
            np.testing.assert_allclose(t_sim, np.arange(len(t_sim)) * 0.05, atol=1e-9)
            assert orphans[0].n_frames == len(t_sim)
    assert hit_a_running_trial >= KILLS // 2


def test_sigint_and_sigterm_end_the_trial_as_application_quit(tmp_path: Path) -> None:
    for signum in (signal.SIGINT, signal.SIGTERM):
        store = tmp_path / f"{signum.name}.sqlite"
        process = collect(store, "--mode", "collection")
        assert process.stdout is not None
        json.loads(process.stdout.readline())  # the first trial ended: the second runs
        wait_for_trials(store, 2)  # past the countdown: the second trial is recorded
        process.send_signal(signum)
        _, err = process.communicate(timeout=60)
        assert process.returncode == 128 + signum, err  # 130, 143: the shells' convention
        assert verify_store(store) == []
        with Store.open(store, writer=False) as reader:
            (session,) = reader.sessions()
            trials = reader.trials()
        assert session.status == "interrupted"
        assert [t.outcome for t in trials] == ["success", "interrupted"]
        assert trials[-1].interruption_reason == "application_quit"


def test_a_closed_standard_output_ends_the_run_like_sigint(tmp_path: Path) -> None:
    """``workcell collect --json ... | head -n 1``: no traceback, the running trial ends
    interrupted (application_quit), the session is closed, the store verifies."""
    store = tmp_path / "pipe.sqlite"
    process = collect(store, "--mode", "collection", "--trials", "3")
    assert process.stdout is not None and process.stderr is not None
    first = json.loads(process.stdout.readline())  # what head -n 1 reads, then it exits
    wait_for_trials(store, 2)  # past the next trial's countdown: its trial row exists
    process.stdout.close()
    err = process.stderr.read()
    process.wait(timeout=60)
    assert process.returncode == 128 + signal.SIGPIPE, err
    assert "Traceback" not in err and "BrokenPipe" not in err, err
    assert first["outcome"] == "success"
    assert verify_store(store) == []
    with Store.open(store, writer=False) as reader:
        (session,) = reader.sessions()
        trials = reader.trials()
    assert session.status == "interrupted"
    assert [t.outcome for t in trials] == ["success", "interrupted"]
    assert trials[-1].interruption_reason == "application_quit"


def _limit_file_size(limit: int) -> Callable[[], None]:
    def apply() -> None:
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
        resource.setrlimit(resource.RLIMIT_FSIZE, (limit, limit))

    return apply


def test_a_file_size_limit_stops_recording_with_storage_error(tmp_path: Path) -> None:
    store = tmp_path / "full.sqlite"
    process = collect(store, "--mode", "collection", preexec_fn=_limit_file_size(3_000_000))
    out, err = process.communicate(timeout=120)
    assert process.returncode == 1
    errors = [line for line in err.splitlines() if line.startswith("workcell: error:")]
    assert len(errors) == 1, err
    assert "file-size limit" in errors[0] and "Traceback" not in err
    assert verify_store(store) == []  # the session was closed: nothing left to recover
    with Store.open(store, writer=False) as reader:
        (session,) = reader.sessions()
        trials = reader.trials()
    assert session.status == "interrupted"
    assert (trials[-1].outcome, trials[-1].interruption_reason) == ("interrupted", "storage_error")
    assert trials[0].outcome == "success"
    last = json.loads(out.splitlines()[-1])
    assert (last["outcome"], last["interruption_reason"]) == ("interrupted", "storage_error")


def test_a_killed_store_writer_ends_the_run_as_storage_error(tmp_path: Path) -> None:
    """The store writer process dies under ``collect``: the run stops at the next
    hand-over, and the store says what was printed: storage_error, session closed."""
    store = tmp_path / "writer.sqlite"
    process = collect(store, "--mode", "collection")
    wait_for_recording(store)
    os.kill(writer_of(process.pid), signal.SIGKILL)
    out, err = process.communicate(timeout=120)
    assert process.returncode == 1, err
    (error,) = [line for line in err.splitlines() if line.startswith("workcell: error:")]
    assert "the store writer process was killed (SIGKILL)" in error
    assert "Traceback" not in err
    last = json.loads(out.splitlines()[-1])
    assert (last["outcome"], last["interruption_reason"]) == ("interrupted", "storage_error")
    assert verify_store(store) == []
    with Store.open(store, writer=False) as reader:
        (session,) = reader.sessions()
        trial = reader.trials()[-1]
        (event,) = [e for e in reader.events(trial.trial_id) if e.kind == "interruption"]
    assert session.status == "interrupted"  # closed by collect itself, not by recovery
    assert (trial.outcome, trial.interruption_reason) == ("interrupted", "storage_error")
    assert event.payload["error"] == error.removeprefix("workcell: error: ")


def test_recorded_trial_is_complete_and_consistent(tmp_path: Path) -> None:
    store = tmp_path / "ok.sqlite"
    process = collect(store, "--mode", "collection", "--trials", "2")
    out, err = process.communicate(timeout=120)
    assert process.returncode == 0, err
    printed = [json.loads(line) for line in out.splitlines()]
    with Store.open(store, writer=False) as reader:
        trials = reader.trials()
        frames = [reader.frames(t.trial_id) for t in trials]
    thresholds = metric_thresholds(SessionConfig())
    for trial, columns, row in zip(trials, frames, printed, strict=True):
        t_sim = columns["t_sim"]
        # the realized sampling rate on the sim clock is exactly the configured rate
        assert (len(t_sim) - 1) / (t_sim[-1] - t_sim[0]) == pytest.approx(20.0, abs=1e-9)
        np.testing.assert_allclose(np.diff(t_sim), 0.05, atol=1e-9)
        assert np.all(np.diff(columns["t_wall"]) > 0)
        # the trial row agrees with what collect printed and with its own frames
        assert trial.outcome == row["outcome"] == "success"
        assert trial.n_frames == len(t_sim)
        assert trial.completion_time_s == pytest.approx(t_sim[-1], abs=1e-9)
        assert trial.elapsed_s == pytest.approx(row["elapsed_s"], abs=1e-6)
        recomputed = compute_trial_metrics(FrameArrays.from_columns(columns), True, thresholds)
        assert trial.metrics.path_length_m == pytest.approx(recomputed.path_length_m)
        assert trial.metrics.active_ratio == pytest.approx(recomputed.active_ratio)
        # every non-device column is filled; the expert's grip is its follow flag
        for name in FRAME_COLUMNS:
            if name not in FRAME_DEVICE_COLUMNS and columns[name].dtype.kind == "f":
                assert np.isfinite(columns[name]).all(), name
        np.testing.assert_array_equal(columns["grip_l"], columns["follow_l"])
        assert columns["trigger_l"].max() == 1.0  # the grippers closed at some point
        assert (columns["attached"] >= 0).any()  # and held a box

"""Real processes, real signals: SIGKILL at random moments, SIGINT and SIGTERM, and a
reader working while a writer process writes."""

from __future__ import annotations

import os
import random
import signal
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np
import pytest

from tests.record import synthetic
from tests.record.processes import finish, next_count, start_writer
from workcell.record import Store
from workcell.record.export_csv import columns_equal
from workcell.record.verify import verify_store

KILLS = 20
PARALLEL = 4
MAX_DELAY_S = 0.3


def _kill_at(store: Path, delay: float, pause: float) -> int:
    """Start a writer, let it commit once, SIGKILL it ``delay`` s later; the last frame
    count it printed (every printed count was committed before it was printed)."""
    process = start_writer(store, "--seed", "3", "--pause", str(pause))
    seen = next_count(process)
    time.sleep(delay)
    os.kill(process.pid, signal.SIGKILL)
    last, _ = finish(process, seen)
    assert process.returncode == -signal.SIGKILL
    return last


def _assert_committed_frames_intact(store: Store, trial_id: str, at_least: int) -> int:
    frames = store.frames(trial_id)
    n = len(frames["frame_index"])
    assert n >= at_least
    expected = synthetic.frames(0, n, seed=3)
    for name, values in expected.items():
        assert columns_equal(frames[name], np.asarray(values, dtype=frames[name].dtype)), name
    return n


def test_sigkill_at_random_moments_loses_no_committed_frame(tmp_path: Path) -> None:
    rng = random.Random(20240611)
    # half the writers commit back to back (kills land mid-write), half pause 2 ms
    runs = [
        (tmp_path / f"kill{k}.db", rng.uniform(0.0, MAX_DELAY_S), 0.002 * (k % 2))
        for k in range(KILLS)
    ]
    with ThreadPoolExecutor(PARALLEL) as pool:
        printed = list(pool.map(lambda run: _kill_at(*run), runs))
    for (path, _, _), last in zip(runs, printed, strict=True):
        with Store.open(path, writer=True) as store:
            (trial,) = store.trials()
            assert store.recovered == (trial.trial_id,)
            assert (trial.outcome, trial.interruption_reason) == ("interrupted", "crash_recovered")
            assert (trial.included, trial.exclusion_reason) == (
                False,
                "incomplete: interrupted (crash_recovered)",
            )  # incomplete, never included
            n = _assert_committed_frames_intact(store, trial.trial_id, at_least=last)
            assert trial.n_frames == n
            assert trial.elapsed_s == pytest.approx((n - 1) / synthetic.RATE_HZ)
            last_frame = synthetic.frame_rows(n - 1, 1, seed=3)[0]
            assert (trial.stage, trial.progress) == (last_frame["stage"], last_frame["progress"])
            assert store.sessions()[0].status == "recovered"
            assert [e.kind for e in store.events(trial.trial_id)] == ["interruption"]
        assert verify_store(path) == [], path
        with Store.open(path, writer=True) as again:  # recovery happens once
            assert again.recovered == ()


@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGTERM])
def test_sigint_and_sigterm_close_the_trial_as_application_quit(
    tmp_path: Path, signum: signal.Signals
) -> None:
    path = tmp_path / "s.db"
    process = start_writer(path, "--seed", "3", "--pause", "0.005")
    for _ in range(3):
        seen = next_count(process)
    process.send_signal(signum)
    last, err = finish(process, seen)
    assert process.returncode == 0, err
    with Store.open(path, writer=False) as store:
        (trial,) = store.trials()
        assert (trial.outcome, trial.interruption_reason) == ("interrupted", "application_quit")
        assert _assert_committed_frames_intact(store, trial.trial_id, at_least=last) == last
        assert trial.n_frames == last
        assert store.sessions()[0].status == "interrupted"
    assert verify_store(path) == []
    with Store.open(path, writer=True) as store:
        assert store.recovered == ()


def test_a_reader_sees_committed_frames_while_a_writer_process_writes(tmp_path: Path) -> None:
    path = tmp_path / "s.db"
    process = start_writer(path, "--seed", "3", "--pause", "0.005")
    try:
        seen = next_count(process)
        with Store.open(path, writer=False) as reader:
            (trial,) = reader.trials()
            assert trial.outcome is None  # running
            counts = []
            for _ in range(3):
                seen = next_count(process)
                n = _assert_committed_frames_intact(reader, trial.trial_id, at_least=seen)
                counts.append(n)
                time.sleep(0.05)
            assert counts[-1] > counts[0]  # new commits became visible to the open reader
            assert process.poll() is None
        assert verify_store(path) == []  # a live recorder's running trial is no problem
    finally:
        process.send_signal(signal.SIGTERM)
        finish(process)
    assert process.returncode == 0

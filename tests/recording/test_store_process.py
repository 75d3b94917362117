"""Recording through the store writer process: same record as in-process, failures raised
in order, nothing sent is lost when the recording process dies."""

from __future__ import annotations

import math
import os
import signal
import subprocess
import sys
import textwrap
import threading
import time
from pathlib import Path

import numpy as np
import pytest

from tests.record import synthetic
from tests.record.processes import wait_until_dead
from workcell.control.command import Command
from workcell.control.simulation import Simulation
from workcell.record import RecordError, StorageError, Store, StoreError
from workcell.record.verify import verify_store
from workcell.recording.frame_capture import CapturedFrames, FrameCapture, input_from_command
from workcell.recording.in_process import InProcessStore
from workcell.recording.recorder import Recorder
from workcell.recording.store_process import StoreProcess
from workcell.session.config import SessionConfig, TaskConfig
from workcell.task.runner import SessionRunner
from workcell.tasks.box_transfer.task import BoxTransfer
from workcell.tasks.elements.expert import ExpertOperator

REPO = Path(__file__).resolve().parents[2]
WALL_CLOCK_COLUMNS = ("t_wall", "step_wall_ms")


def _record(store: InProcessStore | StoreProcess, config: SessionConfig) -> None:
    runner = SessionRunner(
        config, Simulation(config.world, BoxTransfer().scene()), ExpertOperator()
    )
    recorder = Recorder(store, runner)
    runner.run()
    recorder.close(interrupted=False)
    assert recorder.failure is None


@pytest.mark.slow
def test_the_writer_process_records_what_the_store_records_in_process(tmp_path: Path) -> None:
    config = SessionConfig(task=TaskConfig(mode="collection", trials=2), seed=4)
    inline, child = tmp_path / "inline.sqlite", tmp_path / "child.sqlite"
    with InProcessStore.open(inline, writer=True) as store:
        _record(store, config)
    with StoreProcess.open(child) as process_store:
        _record(process_store, config)
    assert verify_store(inline) == [] and verify_store(child) == []
    with Store.open(inline, writer=False) as a, Store.open(child, writer=False) as b:
        trials_a, trials_b = a.trials(), b.trials()
        assert [t.n_frames for t in trials_a] == [t.n_frames for t in trials_b]
        assert all((t.n_frames or 0) > 100 for t in trials_a)
        for ta, tb in zip(trials_a, trials_b, strict=True):
            assert ta.outcome == tb.outcome
            for metric in ("path_length_m", "smoothness", "active_ratio", "hz_sim"):
                assert getattr(ta.metrics, metric) == getattr(tb.metrics, metric), metric
            fa, fb = a.frames(ta.trial_id), b.frames(tb.trial_id)
            for name in fa:
                if name in ("session_id", "trial_id", *WALL_CLOCK_COLUMNS):
                    continue
                if fa[name].dtype == object:
                    assert list(fa[name]) == list(fb[name]), name
                else:
                    np.testing.assert_array_equal(fa[name], fb[name], err_msg=name)
        assert [e.kind for e in a.events()] == [e.kind for e in b.events()]
        for trial in trials_b:  # events are stamped when they happen, not when written
            (started,) = [e for e in b.events(trial.trial_id) if e.kind == "trial_started"]
            first_frame_wall = float(b.frames(trial.trial_id)["t_wall"][0])
            assert started.t_wall <= first_frame_wall


def test_the_frame_ring_is_made_before_the_first_trial_and_once(tmp_path: Path) -> None:
    config = SessionConfig(task=TaskConfig(mode="collection", trials=2), seed=4)
    runner = SessionRunner(
        config, Simulation(config.world, BoxTransfer().scene()), ExpertOperator()
    )
    with StoreProcess.open(tmp_path / "s.sqlite") as store:
        recorder = Recorder(store, runner)
        ring = store._ring
        assert ring is not None and ring.published == 0  # made at once, before any frame
        runner.run()
        recorder.close(interrupted=False)
        assert store._ring is ring and ring.published == recorder.frames_written > 100


def _capture(n: int = 5) -> FrameCapture:
    sim = Simulation(SessionConfig().world, BoxTransfer().scene())
    sim.reset(0)
    return FrameCapture(sim.world, sim.controller, capacity=n)


def _frames(capture: FrameCapture, start: int) -> CapturedFrames:
    """``capture.capacity`` frames of a resting robot, from frame ``start`` at 20 Hz."""
    command = Command()
    for k in range(start, start + capture.capacity):
        capture.capture(command, input_from_command(command), t_sim=k / 20, step_wall_ms=1.0)
    return capture.take()


def test_a_failure_of_a_call_not_waited_for_is_raised_by_the_next_call(tmp_path: Path) -> None:
    capture = _capture()
    frames = _frames(capture, 0)
    with StoreProcess.open(tmp_path / "s.sqlite") as store:
        session_id = store.create_session(synthetic.session_info())
        trial_id = store.start_trial(session_id, synthetic.trial_start())
        store.add_captured_frames(trial_id, frames)
        store.commit()
        with pytest.raises(RecordError, match="no-such-trial was not started"):
            store.add_captured_frames("no-such-trial", _frames(capture, 5))
        store.add_event("no-such-session", "note")  # returns at once
        store.commit()
        # raised by end_trial (if the report came back already) or by end_session
        with pytest.raises(RecordError, match="no-such-session is not running"):
            store.end_trial(trial_id, synthetic.trial_end(len(frames)))
            store.end_session(session_id)
        with pytest.raises(RecordError):  # the writer stays stopped
            store.commit()
    with Store.open(tmp_path / "s.sqlite", writer=True) as reopened:
        (trial,) = reopened.trials()
        assert trial.n_frames == len(frames)  # what came before the failure is kept
    assert verify_store(tmp_path / "s.sqlite") == []


def test_a_filling_ring_wakes_a_writer_that_would_poll_only_much_later(tmp_path: Path) -> None:
    capture = _capture(8)
    batches = [_frames(capture, 8 * k) for k in range(150)]  # 1200 frames, ring of 512
    done = threading.Event()
    with StoreProcess.open(tmp_path / "s.sqlite", poll_s=3600.0) as store:
        session_id = store.create_session(synthetic.session_info())
        store.prepare_frames(capture.layout)
        trial_id = store.start_trial(session_id, synthetic.trial_start())

        def hand_over() -> None:
            for frames in batches:
                store.add_captured_frames(trial_id, frames)
                store.commit()
            done.set()

        worker = threading.Thread(target=hand_over, daemon=True)
        worker.start()
        worker.join(timeout=60)
        # without a wake-up the recorder would wait for a free slot for an hour
        assert done.is_set(), "handing over frames stalled on a full ring"
        store.end_trial(trial_id, synthetic.trial_end(1200))
        store.end_session(session_id)
    with Store.open(tmp_path / "s.sqlite", writer=False) as reader:
        (trial,) = reader.trials()
        assert trial.n_frames == 1200
        np.testing.assert_array_equal(reader.frames(trial.trial_id)["frame_index"], range(1200))
    assert verify_store(tmp_path / "s.sqlite") == []


@pytest.mark.parametrize("poll_s", [0.0, -1.0, math.nan, math.inf])
def test_a_bad_poll_interval_is_one_clear_error(tmp_path: Path, poll_s: float) -> None:
    with pytest.raises(RecordError, match="poll_s: must be a positive number of seconds"):
        StoreProcess.open(tmp_path / "s.sqlite", poll_s=poll_s)
    assert not (tmp_path / "s.sqlite").exists()  # nothing was started


def test_opening_fails_with_the_store_error_and_leaves_no_process(tmp_path: Path) -> None:
    with pytest.raises(StoreError, match="does not exist"):
        StoreProcess.open(tmp_path / "missing" / "s.sqlite")
    with StoreProcess.open(tmp_path / "s.sqlite") as first:
        with pytest.raises(StoreError, match="already open for writing"):
            StoreProcess.open(tmp_path / "s.sqlite")
        first.create_session(synthetic.session_info())


def test_a_dead_writer_process_stops_recording_with_a_storage_error(tmp_path: Path) -> None:
    frames = _frames(_capture(), 0)
    store = StoreProcess.open(tmp_path / "s.sqlite")
    session_id = store.create_session(synthetic.session_info())
    trial_id = store.start_trial(session_id, synthetic.trial_start())
    store.commit()  # sent, not waited for: wait until a reader sees the trial
    deadline = time.monotonic() + 30
    while not _trial_ids(tmp_path / "s.sqlite"):
        assert time.monotonic() < deadline
        time.sleep(0.01)
    os.kill(store.pid, signal.SIGKILL)
    wait_until_dead(store.pid)
    # the very next hand-over notices (one batch, 0.25 s of sim time), with no message sent
    with pytest.raises(StorageError, match=r"store writer process was killed \(SIGKILL\)"):
        store.add_captured_frames(trial_id, frames)
    # and this process closes the session itself, with the reason the operator is told
    assert store.try_interrupt_session(session_id, "storage_error") is True
    store.close()
    with Store.open(tmp_path / "s.sqlite", writer=True) as reopened:
        assert reopened.recovered == ()  # nothing was left for crash recovery
        (session,) = reopened.sessions()
        (trial,) = reopened.trials()
        events = reopened.events(trial_id)
    assert session.status == "interrupted"
    assert (trial.outcome, trial.interruption_reason) == ("interrupted", "storage_error")
    assert events[-1].kind == "interruption"
    assert "store writer process was killed (SIGKILL)" in str(events[-1].payload["error"])
    assert verify_store(tmp_path / "s.sqlite") == []


def _trial_ids(path: Path) -> list[str]:
    with Store.open(path, writer=False) as reader:
        return [t.trial_id for t in reader.trials()]


RECORDER_SCRIPT = textwrap.dedent(
    """
    import os, signal, sys
    from tests.record import synthetic
    from tests.recording.test_store_process import _capture, _frames
    from workcell.recording.store_process import StoreProcess

    store = StoreProcess.open(sys.argv[1])
    session_id = store.create_session(synthetic.session_info())
    trial_id = store.start_trial(session_id, synthetic.trial_start())
    capture = _capture(5)
    for batch in range(int(sys.argv[2])):
        store.add_captured_frames(trial_id, _frames(capture, 5 * batch))
        store.commit()
    print(store._ring.path, flush=True)  # removed already; the writer removes it too
    os.kill(os.getpid(), signal.SIGKILL)
    """
)


def test_what_was_sent_survives_the_death_of_the_recording_process(tmp_path: Path) -> None:
    path = tmp_path / "s.sqlite"
    batches = 40
    result = subprocess.run(
        [sys.executable, "-c", RECORDER_SCRIPT, str(path), str(batches)],
        cwd=REPO,
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    assert result.returncode == -signal.SIGKILL, result.stderr
    assert not Path(result.stdout.strip()).exists()
    with Store.open(path, writer=True) as store:  # waits for the writer to finish
        (trial,) = store.trials()
        assert store.recovered == (trial.trial_id,)
        assert trial.n_frames == 5 * batches  # every batch sent was written
        assert (trial.outcome, trial.interruption_reason) == ("interrupted", "crash_recovered")
    assert verify_store(path) == []


def test_the_writer_removes_its_ring_file_when_the_recorder_could_not(tmp_path: Path) -> None:
    layout = _capture().layout
    store = StoreProcess.open(tmp_path / "s.sqlite")
    # as if the recording process died between the writer making the ring and mapping it
    ring_path = Path(store._call("create_ring", layout, 8))
    assert ring_path.exists()
    store.close()
    assert not ring_path.exists()

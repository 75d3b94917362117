"""Writing and reading back sessions, trials, events, frames and annotations."""

from __future__ import annotations

import hashlib
import math
import os
import signal
from pathlib import Path

import numpy as np
import pytest

from tests.record import synthetic
from workcell.record import RecordError, Store, TrialEnd
from workcell.record.batch import RowBatch, frames_from_columns
from workcell.record.columns import FRAME_COLUMNS
from workcell.record.export_csv import columns_equal, export_csv
from workcell.record.schema import SESSIONS
from workcell.record.verify import verify_store
from workcell.recording.shutdown import ShutdownSignals


def _assert_frames_equal(stored: dict[str, np.ndarray], expected: dict[str, np.ndarray]) -> None:
    for name, values in expected.items():
        column = stored[name]
        assert columns_equal(column, np.asarray(values, dtype=column.dtype)), name


def test_round_trip_of_every_layer(tmp_path: Path) -> None:
    path = tmp_path / "s.db"
    ids = synthetic.fill_store(path)
    with Store.open(path, writer=False) as store:
        sessions = store.sessions()
        assert [s.session_id for s in sessions] == ids["sessions"]
        assert sessions[0].parameters == synthetic.session_info().parameters
        assert sessions[0].thresholds["grip"] == 0.5
        assert sessions[0].status == "completed" and sessions[0].ended_wall is not None
        trials = store.trials()
        assert [t.trial_id for t in trials] == ids["trials"]
        first, second = trials[0], trials[1]
        assert (first.outcome, first.n_frames, first.score) == ("success", 12, 160)
        assert first.quality_flags == ("low_hz_wall",) and first.included is True
        assert math.isnan(first.metrics.smoothness) and first.metrics.path_length_m == 1.25
        assert (second.outcome, second.interruption_reason) == ("interrupted", "operator_stop")
        assert second.included is False and second.exclusion_reason == "interrupted"
        assert [e.kind for e in store.events(first.trial_id)] == ["trial_start", "delivery"]
        assert [e.seq for e in store.events(session_id=ids["sessions"][0])] == list(range(5))
        (note,) = store.annotations(first.trial_id)
        assert (note.kind, note.by) == ("exclude", "reviewer@lab")
        frames = store.frames(first.trial_id)
        assert tuple(frames) == FRAME_COLUMNS
        _assert_frames_equal(frames, synthetic.frames(0, 12, seed=0))
        assert set(frames["trial_id"]) == {first.trial_id}
        assert frames["frame_index"].dtype == np.int64 and frames["boxes"].dtype == object
        assert np.isnan(frames["ctrl_l_x"][0]) and np.isnan(frames["buttons_l"][0])
        assert store.counts().frames == 2 * (12 + 7)
    assert verify_store(path) == []


def test_rows_and_columns_store_the_same_frames(tmp_path: Path) -> None:
    with Store.open(tmp_path / "s.db", writer=True) as store:
        session_id = store.create_session(synthetic.session_info())
        stored = []
        for as_rows in (False, True):
            trial_id = store.start_trial(session_id, synthetic.trial_start())
            data = synthetic.frame_rows(0, 9) if as_rows else synthetic.frames(0, 9)
            assert store.add_frames(trial_id, synthetic.batch(store, trial_id, data)) == 9
            store.end_trial(trial_id, synthetic.trial_end(9))
            stored.append(store.frames(trial_id))
        for name in FRAME_COLUMNS[2:]:
            assert columns_equal(stored[0][name], stored[1][name]), name


def test_frames_left_unnumbered_are_numbered_on_from_the_trials_next_frame(
    tmp_path: Path,
) -> None:
    with Store.open(tmp_path / "s.db", writer=True) as store:
        session_id = store.create_session(synthetic.session_info())
        trial_id = store.start_trial(session_id, synthetic.trial_start())
        for start in (0, 5):
            columns = synthetic.frames(start, 5)
            del columns["frame_index"]
            assert store.next_frame(trial_id) == (session_id, start)
            store.add_frames(trial_id, frames_from_columns(columns, session_id, trial_id, start))
        assert list(store.frames(trial_id)["frame_index"]) == list(range(10))


def test_the_store_takes_only_a_frames_batch_of_the_running_trial(tmp_path: Path) -> None:
    with Store.open(tmp_path / "s.db", writer=True) as store:
        session_id = store.create_session(synthetic.session_info())
        first = store.start_trial(session_id, synthetic.trial_start())
        with pytest.raises(RecordError, match="expected a RowBatch of the frames layout, got dict"):
            store.add_frames(first, synthetic.frames(0, 5))  # type: ignore[arg-type]
        store.end_trial(first, synthetic.trial_end(0))
        second = store.start_trial(session_id, synthetic.trial_start())
        other = frames_from_columns(synthetic.frames(0, 5), session_id, first)
        with pytest.raises(RecordError, match=r"frames row 0: session_id, trial_id .* are not"):
            store.add_frames(second, other)
        session = RowBatch(SESSIONS, [], np.zeros((0, len(SESSIONS.of_kind("real")))), [])
        with pytest.raises(RecordError, match="a sessions batch cannot be added as frames"):
            store.add_frames(second, session)
        store.commit()
        assert store.next_frame(second) == (session_id, 0)


def test_malformed_frames_are_refused_and_nothing_is_lost(tmp_path: Path) -> None:
    path = tmp_path / "s.db"
    with Store.open(path, writer=True) as store:
        session_id = store.create_session(synthetic.session_info())
        trial_id = store.start_trial(session_id, synthetic.trial_start())
        store.add_frames(trial_id, synthetic.batch(store, trial_id, synthetic.frames(0, 5)))
        with pytest.raises(RecordError, match="continue at frame_index 5"):
            store.add_frames(trial_id, synthetic.batch(store, trial_id, synthetic.frames(6, 5)))
        missing = synthetic.frames(5, 5)
        del missing["base_x"]
        with pytest.raises(RecordError, match="missing base_x"):
            store.add_frames(trial_id, synthetic.batch(store, trial_id, missing))
        with pytest.raises(RecordError, match="unknown speed"):
            store.add_frames(
                trial_id,
                synthetic.batch(store, trial_id, {**synthetic.frames(5, 5), "speed": np.zeros(5)}),
            )
        bad = synthetic.frame_rows(5, 1)
        bad[0]["contact_l"] = 0.5
        with pytest.raises(RecordError, match=r"frames\.contact_l: expected an integer"):
            store.add_frames(trial_id, synthetic.batch(store, trial_id, bad))
        with pytest.raises(RecordError, match="not running"):
            store.add_frames("f" * 32, synthetic.batch(store, "f" * 32, synthetic.frames(0, 5)))
        store.commit()
        assert len(store.frames(trial_id)["frame_index"]) == 5


def test_trial_and_session_rules(tmp_path: Path) -> None:
    with Store.open(tmp_path / "s.db", writer=True) as store:
        session_id = store.create_session(synthetic.session_info())
        trial_id = store.start_trial(session_id, synthetic.trial_start())
        with pytest.raises(RecordError, match="still running"):
            store.start_trial(session_id, synthetic.trial_start())
        with pytest.raises(RecordError, match="still running"):
            store.end_session(session_id)
        store.end_trial(trial_id, synthetic.trial_end(0))
        with pytest.raises(RecordError, match="not running"):
            store.end_trial(trial_id, synthetic.trial_end(0))
        with pytest.raises(RecordError, match="annotation kind"):
            store.annotate(trial_id, "maybe", "unsure", "me")
        store.end_session(session_id, "interrupted")
        assert store.sessions()[0].status == "interrupted"
    with pytest.raises(RecordError, match="needs one of"):
        TrialEnd(outcome="interrupted", elapsed_s=1.0, boxes_delivered=0, score=0)
    with pytest.raises(RecordError, match="must be one of"):
        TrialEnd(outcome="crashed", elapsed_s=1.0, boxes_delivered=0, score=0)


def test_non_finite_measurements_are_kept_and_reported(tmp_path: Path) -> None:
    path = tmp_path / "s.db"
    with Store.open(path, writer=True) as store:
        session_id = store.create_session(synthetic.session_info())
        trial_id = store.start_trial(session_id, synthetic.trial_start())
        frames = synthetic.frames(0, 5)
        frames["q_spine"][2] = np.nan
        frames["tcp_l_x"][4] = np.inf
        store.add_frames(trial_id, synthetic.batch(store, trial_id, frames))
        store.end_trial(trial_id, synthetic.trial_end(5))
        store.end_session(session_id)
        stored = store.frames(trial_id)
        assert np.isnan(stored["q_spine"][2]) and stored["tcp_l_x"][4] == np.inf
    problems = {(f.row, f.problem) for f in verify_store(path)}
    assert problems == {
        (f"trial {trial_id} frame 2", "q_spine is NULL or NaN (only device columns may be)"),
        (f"trial {trial_id} frame 4", "tcp_l_x is infinite"),
    }


def test_readers_never_modify_the_store(tmp_path: Path) -> None:
    path = tmp_path / "s.db"
    ids = synthetic.fill_store(path)
    with Store.open(path, writer=True) as store:  # leave a trial open, as a crash would
        trial_id = store.start_trial(
            store.create_session(synthetic.session_info()), synthetic.trial_start()
        )
    before = hashlib.sha256(path.read_bytes()).hexdigest()
    with Store.open(path, writer=False) as reader:
        assert reader.recovered == ()
        assert [t.trial_id for t in reader.trials()] == [*ids["trials"], trial_id]
        reader.frames(ids["trials"][0])
    assert len(verify_store(path)) == 2  # the open trial and session, named, not changed
    export_csv(path, tmp_path / "out")
    assert hashlib.sha256(path.read_bytes()).hexdigest() == before


def test_shutdown_signals_set_a_flag_then_interrupt() -> None:
    previous = signal.getsignal(signal.SIGTERM)
    with ShutdownSignals() as shutdown:
        requested = [shutdown.requested]
        os.kill(os.getpid(), signal.SIGTERM)  # handled before kill() returns
        requested.append(shutdown.requested)
        assert requested == [None, "SIGTERM"]
        with pytest.raises(KeyboardInterrupt):
            os.kill(os.getpid(), signal.SIGINT)
    assert signal.getsignal(signal.SIGTERM) == previous

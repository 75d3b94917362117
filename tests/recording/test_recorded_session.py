"""RecordedSession: one session run and recorded (the real world, the expert, a real SQLite
store), stopped by the trial cap, a complete campaign, the writer's death or a request."""

from __future__ import annotations

import os
import pickle
import signal
import threading
import time
from pathlib import Path

import pytest

from tests.record.processes import wait_until_dead, writer_of
from workcell.expert.skill import ExpertConfig
from workcell.record import Store
from workcell.record.verify import verify_store
from workcell.recording.drivers import ExpertDriver
from workcell.recording.recorded_session import (
    RealTime,
    RecordedSession,
    RecordedSessionConfig,
)
from workcell.session.config import SessionConfig, TaskConfig
from workcell.task import events as ev
from workcell.task.pacing import StopRequest
from workcell.task.runner import TrialResult

HAND_OVER_S = 0.25
"""Sim time between two hand-overs of frames to the store writer."""


def _stored(store: Path) -> tuple[str, list[tuple[str | None, str | None]]]:
    """The session's status and each trial's (outcome, interruption reason); the store
    verifies."""
    assert verify_store(store) == []
    with Store.open(store, writer=False) as reader:
        (session,) = reader.sessions()
        trials = [(t.outcome, t.interruption_reason) for t in reader.trials()]
    return session.status, trials


def test_it_stops_at_the_trial_count_from_a_pickled_configuration(tmp_path: Path) -> None:
    task = TaskConfig(mode="collection", trials=0, time_limit_s=1.0, countdown_s=0.0)
    config = RecordedSessionConfig(
        session=SessionConfig(seed=3, task=task),
        driver=ExpertDriver(ExpertConfig(skill=0.5)),
        store=tmp_path / "s.sqlite",
        writer="inline",
        max_trials=2,
    )
    config = pickle.loads(pickle.dumps(config))  # what a session's own process receives
    seen: list[TrialResult] = []
    steps = 0

    def count() -> None:
        nonlocal steps
        steps += 1

    with RecordedSession.open(config) as session:
        ended = session.run(after_step=count, on_trial=seen.append)
    assert ended == "completed"
    assert session.runner.capped and not session.runner.campaign_complete
    assert [(r.spec.trial_index, r.outcome) for r in seen] == [(0, "timeout"), (1, "timeout")]
    assert steps == 2 * 40  # two 1 s trials at 40 Hz, no countdown
    assert session.frames_written == 2 * 21  # 20 Hz frames from t = 0 to t = 1 s
    assert _stored(tmp_path / "s.sqlite") == ("completed", [("timeout", None), ("timeout", None)])


def test_it_stops_when_the_campaign_is_complete(tmp_path: Path) -> None:
    task = TaskConfig(
        mode="challenge", rounds=1, level_boxes=(1,), level_time_limits_s=(60.0,), countdown_s=0.0
    )
    config = RecordedSessionConfig(
        session=SessionConfig(seed=1, task=task),
        store=tmp_path / "s.sqlite",
        writer="inline",
        max_trials=5,
    )
    with RecordedSession.open(config) as session:
        ended = session.run()
    assert ended == "completed"
    assert session.runner.campaign_complete and not session.runner.capped
    assert [r.outcome for r in session.runner.results] == ["success"]
    assert _stored(tmp_path / "s.sqlite") == ("completed", [("success", None)])


def test_a_dead_writer_ends_the_session_as_storage_error_within_one_hand_over(
    tmp_path: Path,
) -> None:
    task = TaskConfig(mode="practice", time_limit_s=30.0, countdown_s=0.0)
    config = RecordedSessionConfig(session=SessionConfig(task=task), store=tmp_path / "s.sqlite")
    killed_at: list[float] = []
    with RecordedSession.open(config) as session:
        writer = writer_of(os.getpid())
        runner = session.runner

        def kill_at_one_second() -> None:
            if not killed_at and runner.trial_time >= 1.0:
                os.kill(writer, signal.SIGKILL)
                wait_until_dead(writer)  # the simulation waits: the death lands at 1 s
                killed_at.append(runner.trial_time)

        ended = session.run(after_step=kill_at_one_second)
    assert ended == "storage_error"
    assert session.failure is not None and "was killed (SIGKILL)" in str(session.failure)
    (result,) = session.runner.results
    assert (result.outcome, result.interruption_reason) == ("interrupted", "storage_error")
    assert result.elapsed_s - killed_at[0] <= HAND_OVER_S + 1e-9
    assert _stored(tmp_path / "s.sqlite") == ("interrupted", [("interrupted", "storage_error")])


def test_a_dead_writer_stops_the_session_at_the_next_control_period_as_the_store_says(
    tmp_path: Path,
) -> None:
    """The writer dies just after a hand-over of frames: the session stops at the next
    control period, not at the next hand-over, and the trial's elapsed time, in the results
    and in the TrialEnded its listeners hear, is the one the store closed it with."""
    task = TaskConfig(mode="practice", time_limit_s=30.0, countdown_s=0.0)
    config = RecordedSessionConfig(session=SessionConfig(task=task), store=tmp_path / "s.sqlite")
    killed_at: list[float] = []
    heard: list[ev.TrialEnded] = []
    with RecordedSession.open(config) as session:
        writer = writer_of(os.getpid())
        runner = session.runner
        runner.bus.subscribe(lambda e: heard.append(e) if isinstance(e, ev.TrialEnded) else None)
        assert session.recorder is not None
        store = session.recorder.store

        def kill_at_one_second() -> None:  # frames were handed over at 0.95 s
            if not killed_at and runner.trial_time >= 1.0:
                os.kill(writer, signal.SIGKILL)
                deadline = time.monotonic() + 30
                while not store.failure_pending():  # the store heard the writer's pipe close
                    assert time.monotonic() < deadline, "the writer's death went unnoticed"
                    time.sleep(0.005)
                killed_at.append(runner.trial_time)

        ended = session.run(after_step=kill_at_one_second)
    assert ended == "storage_error"
    assert runner.trial_time - killed_at[0] <= session.sim.control_dt + 1e-9
    with Store.open(tmp_path / "s.sqlite", writer=False) as reader:
        (trial,) = reader.trials()
    (result,) = runner.results
    (told,) = heard
    assert (trial.outcome, trial.interruption_reason) == ("interrupted", "storage_error")
    assert told.elapsed_s == result.elapsed_s == trial.elapsed_s
    assert told.t_sim == trial.elapsed_s


def test_a_failure_while_a_trial_ends_is_what_the_results_and_the_store_both_say(
    tmp_path: Path,
) -> None:
    """The writer stops after the trial's last hand-over of frames and dies as the trial's
    timeout is sent to it, so the failure comes as that end is written: the store closes
    the trial interrupted (storage_error), and the results say so too, without the next
    trial the runner began, which was never recorded."""
    task = TaskConfig(mode="collection", trials=0, time_limit_s=1.0, countdown_s=0.0)
    config = RecordedSessionConfig(
        session=SessionConfig(seed=3, task=task),
        driver=ExpertDriver(ExpertConfig(skill=0.5)),
        store=tmp_path / "s.sqlite",
        max_trials=3,
    )
    reported: list[TrialResult] = []
    signalled: list[signal.Signals] = []
    with RecordedSession.open(config) as session:
        writer = writer_of(os.getpid())
        runner = session.runner

        def stop_after_the_last_hand_over() -> None:
            if runner.trial_time >= 0.975 and not signalled:
                os.kill(writer, signal.SIGSTOP)  # what is sent now stays unread
                signalled.append(signal.SIGSTOP)

        def kill_as_the_trial_ends(event: ev.TaskEvent) -> None:
            if isinstance(event, ev.TrialEnded) and signalled == [signal.SIGSTOP]:
                os.kill(writer, signal.SIGKILL)  # the recorder has sent the trial's end
                wait_until_dead(writer)
                signalled.append(signal.SIGKILL)

        runner.bus.subscribe(kill_as_the_trial_ends)  # called after the recorder
        ended = session.run(after_step=stop_after_the_last_hand_over, on_trial=reported.append)
    assert ended == "storage_error"
    expected = [(0, "interrupted", "storage_error")]
    assert [(r.spec.trial_index, r.outcome, r.interruption_reason) for r in reported] == expected
    assert reported == session.runner.results
    (result,) = reported
    assert result.completion_time_s is None and result.elapsed_s == pytest.approx(1.0)
    assert _stored(tmp_path / "s.sqlite") == ("interrupted", [("interrupted", "storage_error")])


def test_a_stop_request_from_another_thread_ends_a_paced_session(tmp_path: Path) -> None:
    task = TaskConfig(mode="practice", time_limit_s=30.0, countdown_s=0.0)
    config = RecordedSessionConfig(
        session=SessionConfig(task=task), store=tmp_path / "s.sqlite", real_time=RealTime()
    )
    stop = StopRequest()
    with RecordedSession.open(config, stop) as session:
        timer = threading.Timer(0.5, stop.request, ("operator_stop",))
        timer.start()
        started = time.monotonic()
        ended = session.run()
        wall_s = time.monotonic() - started
        timer.join()
    assert ended == "operator_stop"
    steps = session.pacing.steps
    assert 0 < steps <= wall_s * 40 + 1  # 40 Hz on the wall clock, not as fast as it goes
    assert session.runner.results[0].elapsed_s == pytest.approx(steps / 40)
    assert _stored(tmp_path / "s.sqlite") == ("interrupted", [("interrupted", "operator_stop")])

"""The real-time loop: pacing against a clock, and a live session on its own thread."""

from __future__ import annotations

import dataclasses
import itertools
import threading
import time
from pathlib import Path

import pytest

from workcell.errors import ConfigError
from workcell.protocol import messages as m
from workcell.protocol.codec import decode_server
from workcell.record.store import Store
from workcell.server.live import LiveSession
from workcell.session.config import SessionConfig
from workcell.session.toml_io import from_mapping
from workcell.task import events as ev
from workcell.task.hud import HudPhase
from workcell.task.pacing import Pacer
from workcell.task.runner import SessionRunner
from workcell.teleop.rate import at_teleop_rate


class FakeClock:
    def __init__(self) -> None:
        self.now = 0.0

    def __call__(self) -> float:
        return self.now


class FakeStop(threading.Event):
    """A stop event whose waiting advances the fake clock instead of sleeping."""

    def __init__(self, clock: FakeClock) -> None:
        super().__init__()
        self.clock = clock

    def wait(self, timeout: float | None = None) -> bool:
        self.clock.now += timeout or 0.0
        return self.is_set()


def test_pacer_keeps_the_grid_catches_up_and_drops_long_stalls() -> None:
    clock = FakeClock()
    pacer = Pacer(period=0.025, max_catch_up_s=0.25, clock=clock)
    stop = FakeStop(clock)
    for _ in range(4):  # on time: each step waits for its slot
        assert pacer.wait(stop)
        clock.now += 0.005
        pacer.done()
    assert clock.now == pytest.approx(0.08)
    assert pacer.stats.late_steps == 0
    clock.now += 0.1  # a 0.1 s stall: the next steps run back to back to catch up
    starts = []
    for _ in range(6):
        assert pacer.wait(stop)
        starts.append(clock.now)
        pacer.done()
    assert starts[1] == starts[0]  # no sleeping while behind
    assert pacer.stats.late_steps >= 2 and pacer.stats.dropped_s == 0.0
    clock.now += 1.0  # a 1 s stall: beyond the catch-up limit, time is dropped
    assert pacer.wait(stop)
    assert pacer.stats.dropped_s > 0.7
    pacer.done()
    assert pacer.wait(stop)  # and the grid restarts from now: one period later
    assert clock.now == pytest.approx(starts[-1] + 1.0 + 0.025)
    stop.set()
    clock.now -= 1.0
    assert not pacer.wait(stop)


def test_a_pacer_with_an_idle_waits_through_it_and_calls_it_before_every_step() -> None:
    """A loop with work to do while it waits (a session's child reading its pipe): the
    pacer waits by calling the idle until the step is due, however early it returns, and
    calls it once even when no wait is left, so what arrived is taken before every step;
    work that stops the loop ends the wait."""
    clock = FakeClock()
    stop = threading.Event()
    calls: list[float] = []

    def idle(seconds: float) -> None:
        calls.append(seconds)
        clock.now += min(seconds, 0.004)  # work arrives every 4 ms: it returns early

    pacer = Pacer(period=0.01, max_catch_up_s=0.25, clock=clock, idle=idle)
    assert pacer.wait(stop)  # the first step is due at once: one look, no wait
    assert calls == [0.0]
    pacer.done()
    calls.clear()
    assert pacer.wait(stop)
    assert calls == pytest.approx([0.01, 0.006, 0.002])
    assert clock.now == pytest.approx(0.01)
    pacer.done()
    clock.now += 0.05  # behind: no waiting, but one look all the same
    calls.clear()
    assert pacer.wait(stop)
    assert calls == [0.0]
    pacer.done()

    def stopping(seconds: float) -> None:
        stop.set()

    pacer.idle = stopping
    assert not pacer.wait(stop)


class Collect:
    def __init__(self) -> None:
        self.states: list[tuple[float, str]] = []
        self.messages: list[str] = []
        self.done = threading.Event()
        self.end: m.SessionEnded | None = None

    def state(self, text: str) -> None:
        self.states.append((time.monotonic(), text))

    def message(self, text: str) -> None:
        self.messages.append(text)

    def ended(self, message: m.SessionEnded) -> None:
        self.end = message
        self.done.set()


CONFIG = from_mapping(SessionConfig, {"task": {"countdown_s": 0.0}})


def test_a_live_session_keeps_real_time_and_caps_states(tmp_path: Path) -> None:
    listener = Collect()
    session = LiveSession(CONFIG, tmp_path / "s.sqlite", listener, state_hz=30.0)
    session.start()
    time.sleep(1.0)
    session.request_stop("operator_stop")
    assert listener.done.wait(10) and session.join(10)
    stats = session.pacing
    assert 90 <= stats.steps <= 110  # a person drives at 100 Hz control for 1 s
    times = [t for t, _ in listener.states]
    assert 25 <= len(times) <= 32  # no input: capped at 30 Hz
    sim_times = [
        s.t_sim for _, text in listener.states if isinstance(s := decode_server(text), m.State)
    ]
    assert min(b - a for a, b in itertools.pairwise(sim_times)) >= 0.0249
    state = decode_server(listener.states[-1][1])
    assert (
        isinstance(state, m.State) and state.hud is not None and state.hud.phase is HudPhase.RUNNING
    )
    kinds = [decode_server(t) for t in listener.messages]
    assert any(isinstance(k, ev.TrialStarted) for k in kinds)
    assert listener.end is not None and listener.end.reason == "operator_stop"
    with Store.open(tmp_path / "s.sqlite", writer=False) as store:
        (trial,) = store.trials()
        (stored,) = store.sessions()
    assert trial.interruption_reason == "operator_stop"
    assert stored.parameters["world"]["robot"]["control_hz"] == 100.0  # the rate it ran at


def test_a_person_drives_at_the_teleop_rate_and_the_expert_at_its_own() -> None:
    assert (CONFIG.world.robot.control_hz, CONFIG.world.robot.teleop_control_hz) == (40.0, 100.0)
    driven = at_teleop_rate(CONFIG)
    assert driven.world.robot.control_hz == 100.0 and driven.world.control_substeps == 4
    assert dataclasses.replace(driven, world=CONFIG.world) == CONFIG  # nothing else changed
    same = from_mapping(SessionConfig, {"world": {"robot": {"teleop_control_hz": 40.0}}})
    assert at_teleop_rate(same) is same
    with pytest.raises(ConfigError, match=r"world\.robot\.teleop_control_hz = 30: must divide"):
        from_mapping(SessionConfig, {"world": {"robot": {"teleop_control_hz": 30.0}}})


def _input(seq: int) -> m.Input:
    hand = m.ControllerState(None, 0.0, 0.0, (0.0, 0.0), 0)
    return m.Input(seq=seq, t_client=0.0, source="xr", headset=None, left=hand, right=hand)


def test_an_input_is_shown_applied_in_the_state_after_the_period_that_applied_it(
    tmp_path: Path,
) -> None:
    """States are due twice a second here, but each new input is acknowledged by a State
    right after the control period that acted on it (input_seq), a period later at most."""
    listener = Collect()
    session = LiveSession(CONFIG, tmp_path / "s.sqlite", listener, state_hz=2.0)
    session.start()
    acknowledged: list[float] = []
    for seq in range(1, 6):
        time.sleep(0.05)
        seen = len(listener.states)
        sent = time.monotonic()
        assert session.operator.submit(_input(seq))
        deadline = sent + 1.0
        while time.monotonic() < deadline and not any(
            isinstance(s := decode_server(text), m.State) and s.input_seq >= seq
            for _, text in listener.states[seen:]
        ):
            time.sleep(0.001)
        acknowledged.append(time.monotonic() - sent)
    session.request_stop("operator_stop")
    assert listener.done.wait(10) and session.join(10)
    assert max(acknowledged) < 0.2, acknowledged  # not the 0.5 s a due State takes
    assert len(listener.states) <= 5 + 2 * 2 + 2  # one per input, plus the due ones


def test_a_failing_simulation_ends_the_session_and_leaves_the_trial_to_recovery(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    calls = {"n": 0}
    step = SessionRunner.step

    def failing(self: SessionRunner) -> None:
        calls["n"] += 1
        if calls["n"] > 10:
            raise RuntimeError("solver exploded")
        step(self)

    monkeypatch.setattr(SessionRunner, "step", failing)
    listener = Collect()
    session = LiveSession(CONFIG, tmp_path / "s.sqlite", listener)
    session.start()
    assert listener.done.wait(10) and session.join(10)
    assert listener.end is not None and listener.end.reason == "error"
    assert listener.end.detail == "solver exploded"
    with Store.open(tmp_path / "s.sqlite", writer=True) as store:  # the next writer recovers
        (trial,) = store.trials()
    assert trial.interruption_reason == "crash_recovered"

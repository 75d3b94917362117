"""Stopping with a reason, pausing, resuming a study step where it stopped, and admission
by measured headroom, over a real server and real sockets."""

from __future__ import annotations

import asyncio
import contextlib
import json
import math
import re
import time
import urllib.error
import urllib.request
from pathlib import Path
from typing import Any

import numpy as np

from tests.server.harness import (
    FAST_SETTINGS,
    Client,
    RunningServer,
    client,
    hand,
    running_server,
)
from tests.server.test_study_server import CONSENT, get_as, token_of
from workcell.audit.run import run_audit
from workcell.audit.sampling import SamplingParams, detect_sampling
from workcell.audit.store_source import StoreSource
from workcell.protocol import messages as m
from workcell.record.store import Store
from workcell.record.verify import verify_store
from workcell.study.config import Condition, Step, StudyConfig
from workcell.study.plan import participant_plan
from workcell.task import events as ev
from workcell.task.runner import trial_seed


async def start(operator: Client, settings: dict[str, Any], consent: bool = False) -> Any:
    await operator.send(m.StartSession(settings=settings, consent=consent))
    return await operator.wait_for(lambda x: isinstance(x, m.SessionStarted | m.Error), 30)


async def event(
    operator: Client, kind: str, timeout: float = 20.0, since: int | None = None
) -> Any:
    """The next event of ``kind``; with ``since``, also one already received from that
    position on (a session's first events may come before its session_started)."""
    if since is not None:
        for message in operator.received[since:]:
            if getattr(message, "kind", None) == kind:
                return message
    return await operator.wait_for(lambda x: getattr(x, "kind", None) == kind, timeout)


async def ended(operator: Client) -> m.SessionEnded:
    message = await operator.wait_for(lambda x: isinstance(x, m.SessionEnded), 30)
    assert isinstance(message, m.SessionEnded)
    return message


def post(server: RunningServer, path: str, token: str, body: bytes) -> tuple[int, Any]:
    request = urllib.request.Request(
        server.http + path,
        data=body,
        method="POST",
        headers={"Authorization": f"Bearer {token}", "Content-Type": "application/json"},
    )
    try:
        with urllib.request.urlopen(request, timeout=10) as response:
            return int(response.status), json.loads(response.read())
    except urllib.error.HTTPError as error:
        return int(error.code), json.loads(error.read())


def stored_events(store: Path, kind: str) -> list[dict[str, Any]]:
    with Store.open(store, writer=False) as reader:
        return [e.payload for e in reader.events() if e.kind == kind]


def test_an_operators_stop_records_their_reason_and_tells_it_back(tmp_path: Path) -> None:
    settings = {"task": {"countdown_s": 0.0, "time_limit_s": 60.0}}

    async def scenario(server: RunningServer) -> None:
        async with client(server) as operator:
            await operator.hello()
            await operator.send(m.Stop(reason="x" * 301))  # too long: refused, nothing stops
            refused = await operator.wait_for(lambda x: isinstance(x, m.Error))
            assert isinstance(refused, m.Error) and "stop.reason" in refused.message
            assert "300" in refused.message
            before = len(operator.received)
            assert isinstance(await start(operator, settings), m.SessionStarted)
            await event(operator, "trial_started", since=before)
            await operator.send(m.Stop(reason="  my headset battery is low "))
            noted = await event(operator, "stop_requested")
            assert (noted.by, noted.reason) == ("operator", "my headset battery is low")
            done = await ended(operator)
            assert (done.reason, done.stop_note) == ("operator_stop", "my headset battery is low")

    with running_server(tmp_path) as server:
        asyncio.run(scenario(server))
    (recorded,) = stored_events(tmp_path / "store.sqlite", "stop_requested")
    assert (recorded["by"], recorded["reason"]) == ("operator", "my headset battery is low")
    assert recorded["trial_index"] == 0


def first_trial(started: m.SessionStarted) -> object:
    task = started.settings["task"]
    assert isinstance(task, dict)
    return task["first_trial"]


def test_a_stop_during_the_countdown_is_recorded_as_the_sessions(tmp_path: Path) -> None:
    """Its trial never started (no row): the stop and its reason are a session event."""
    settings = {"task": {"countdown_s": 30.0, "time_limit_s": 60.0}}

    async def scenario(server: RunningServer) -> None:
        async with client(server) as operator:
            await operator.hello()
            assert isinstance(await start(operator, settings), m.SessionStarted)
            await operator.send(m.Stop(reason="wrong settings"))
            done = await ended(operator)
            assert (done.reason, done.stop_note, done.trials) == (
                "operator_stop",
                "wrong settings",
                0,
            )

    with running_server(tmp_path) as server:
        asyncio.run(scenario(server))
    with Store.open(tmp_path / "store.sqlite", writer=False) as reader:
        assert reader.trials() == []
        (stop,) = [e for e in reader.events() if e.kind == "stop_requested"]
    assert stop.trial_id is None and stop.payload["reason"] == "wrong settings"
    assert verify_store(tmp_path / "store.sqlite") == []


def collection_study(trials: int = 2, time_limit_s: float = 1.0) -> StudyConfig:
    """One condition, one collection step of ``trials`` short trials."""
    return StudyConfig(
        name="resume",
        participants=1,
        instructions="Move the box.",
        consent=CONSENT,
        session={"task": {"countdown_s": 0.0, "time_limit_s": time_limit_s}},
        conditions=(Condition("assisted", {"world.grasp": "assisted"}),),
        steps=(Step("collection", trials),),
    )


def test_the_admins_stop_takes_a_reason_and_refuses_a_bad_body(tmp_path: Path) -> None:
    async def scenario(server: RunningServer) -> None:
        admin = server.options.token
        assert admin is not None
        async with client(server, query=f"?token={token_of(server, 'p01')}") as p01:
            await p01.hello()
            assert isinstance(await start(p01, {}, consent=True), m.SessionStarted)
            path = "/api/study/participants/p01/stop"
            status, body = post(server, path, admin, b'{"reason": 5}')
            assert status == 400 and '"reason": text of at most 300' in body["error"]
            status, body = post(server, path, admin, b"not json")
            assert status == 400 and "not JSON" in body["error"]
            status, body = post(server, path, admin, b"[" * 100_000 + b"]" * 100_000)
            assert status == 400 and "not JSON" in body["error"]  # nested too deep: not a 500
            status, body = post(server, path, admin, b'{"reason": "\\udc00 closing"}')
            assert status == 400 and "lone surrogate" in body["error"]  # the store has no form
            status, _ = post(server, path, admin, b'{"reason": "the session room closes"}')
            assert status == 200
            done = await ended(p01)
            assert (done.reason, done.stop_note) == ("admin_stop", "the session room closes")

    with running_server(tmp_path, study=collection_study(time_limit_s=60.0)) as server:
        asyncio.run(scenario(server))
    (recorded,) = stored_events(tmp_path / "store.sqlite", "stop_requested")
    assert (recorded["by"], recorded["reason"]) == ("admin", "the session room closes")


def test_a_stopped_study_step_resumes_at_the_trial_where_it_stopped(tmp_path: Path) -> None:
    config = collection_study(trials=3)
    (planned,) = participant_plan(config, "p01")

    async def scenario(server: RunningServer) -> None:
        token = token_of(server, "p01")
        async with client(server, query=f"?token={token}") as p01:
            await p01.hello()
            before = len(p01.received)
            first = await start(p01, {}, consent=True)
            assert isinstance(first, m.SessionStarted)
            assert first_trial(first) == 0
            ended_trial = await event(p01, "trial_ended", since=before)  # times out after 1 s
            assert (ended_trial.trial_index, ended_trial.outcome) == (0, "timeout")
            assert (await event(p01, "trial_started")).trial_index == 1
            await p01.send(m.Stop(reason="a break"))
            assert (await ended(p01)).reason == "operator_stop"
            status, me = get_as(server, "/api/study/me", token)
            assert status == 200 and me["done"] == 0
            assert (me["next"]["trials"], me["next"]["trials_done"]) == (3, 1)
            mark = len(p01.received)
            second = await start(p01, {})
            assert isinstance(second, m.SessionStarted), second
            assert first_trial(second) == 1
            assert second.settings["seed"] == planned.config.seed
            assert (await ended(p01)).reason == "completed"
            begun = [x.trial_index for x in p01.received[mark:] if isinstance(x, ev.TrialStarted)]
            assert begun == [1, 2]
            status, me = get_as(server, "/api/study/me", token)
            assert (me["done"], me["next"]) == (1, None)

    with running_server(tmp_path, study=config) as server:
        asyncio.run(scenario(server))
    with Store.open(tmp_path / "store.sqlite", writer=False) as reader:
        sessions = reader.sessions()
        trials = {s.session_id: [] for s in sessions}  # type: dict[str, list[Any]]
        for trial in reader.trials():
            trials[trial.session_id].append(trial)
        started = [e.payload for e in reader.events() if e.kind == "trial_started"]
    assert [s.status for s in sessions] == ["interrupted", "completed"]
    assert [(t.trial_index, t.outcome) for t in trials[sessions[0].session_id]] == [
        (0, "timeout"),
        (1, "interrupted"),
    ]
    # the store numbers a session's trials from 0; their worlds are the plan's trials 1, 2
    seed = planned.config.seed
    assert [(t.trial_seed, t.outcome) for t in trials[sessions[1].session_id]] == [
        (trial_seed(seed, 1), "timeout"),
        (trial_seed(seed, 2), "timeout"),
    ]
    # trial 1 of the resumed session meets the world trial 1 met before the stop
    seeds = [(p["trial_index"], p["trial_seed"]) for p in started]
    assert seeds.count((1, trial_seed(planned.config.seed, 1))) == 2


def test_a_pause_stops_the_clock_and_is_recorded(tmp_path: Path) -> None:
    settings = {"task": {"countdown_s": 0.0, "time_limit_s": 2.0}}
    pause_s = 1.5

    async def scenario(server: RunningServer) -> None:
        async with client(server) as operator:
            await operator.hello()
            await operator.send(m.Pause(paused=True))
            refused = await operator.wait_for(lambda x: isinstance(x, m.Error))
            assert isinstance(refused, m.Error) and "no session is running" in refused.message
            before = len(operator.received)
            assert isinstance(await start(operator, settings), m.SessionStarted)
            await event(operator, "trial_started", since=before)
            await asyncio.sleep(0.5)
            await operator.send(m.Pause(paused=True))
            paused = await event(operator, "paused")
            await asyncio.sleep(pause_s)
            count = len(operator.received)
            await operator.send(m.Pause(paused=False))
            resumed = await event(operator, "resumed")
            during = [
                x
                for x in operator.received[:count]
                if isinstance(x, m.State) and x.t_sim > paused.t_sim
            ]
            assert during == []  # nothing moved while paused
            assert resumed.t_sim == paused.t_sim
            assert resumed.paused_s >= pause_s
            trial = await event(operator, "trial_ended")
            assert (trial.outcome, trial.elapsed_s) == ("timeout", 2.0)
            assert (await ended(operator)).reason == "completed"

    with running_server(tmp_path) as server:
        asyncio.run(scenario(server))
    store = tmp_path / "store.sqlite"
    (resumed,) = stored_events(store, "resumed")
    with Store.open(store, writer=False) as reader:
        (trial,) = reader.trials()
        t_wall = reader.frames(trial.trial_id)["t_wall"]
        kinds = [e.kind for e in reader.events() if e.trial_id == trial.trial_id]
    assert kinds.index("paused") + 1 == kinds.index("resumed")
    assert trial.elapsed_s == 2.0  # the trial's clock: the pause is not in it
    wall_span = float(t_wall[-1] - t_wall[0])
    assert wall_span >= 2.0 - 0.1 + pause_s  # the wall clock: it is
    gaps = np.diff(t_wall)
    assert float(gaps.max()) >= pause_s and resumed["paused_s"] >= pause_s
    # the audit's wall-clock sampling check leaves the pause out: a gap, but no flag for it
    source = StoreSource(store)
    try:
        (audited,) = run_audit(source).trials
        frames = next(iter(source.frames()))[1]
    finally:
        source.close()
    details = " ".join(f.detail for f in audited.flags if f.name == "sampling_gap")
    walls = [float(x) for x in re.findall(r"t_wall: \d+ gap\(s\), largest ([\d.]+) s", details)]
    assert all(wall < pause_s for wall in walls), details  # a stall of the machine, if any
    (unpaused,) = detect_sampling(frames, 20.0, SamplingParams())  # were it not a pause
    assert unpaused.name == "sampling_gap" and "t_wall: 1 gap(s)" in unpaused.detail


def test_a_client_that_comes_in_while_paused_hears_it(tmp_path: Path) -> None:
    settings = {"task": {"countdown_s": 0.0, "time_limit_s": 60.0}}

    async def scenario(server: RunningServer) -> None:
        async with client(server) as operator:
            await operator.hello()
            before = len(operator.received)
            assert isinstance(await start(operator, settings), m.SessionStarted)
            await event(operator, "trial_started", since=before)
            await operator.send(m.Pause(paused=True))
            await event(operator, "paused")
            async with client(server) as late:
                await late.hello(role="spectator")
                told = await event(late, "paused")
                assert told.trial_index == 0
            await operator.send(m.Pause(paused=False))
            await event(operator, "resumed")
            async with client(server) as later:
                await later.hello(role="spectator")
                await later.wait_for(lambda x: isinstance(x, m.Scene))
                with contextlib.suppress(TimeoutError):  # nothing paused to tell now
                    await later.wait_for(lambda x: getattr(x, "kind", None) == "paused", 1.0)
                assert not any(getattr(x, "kind", None) == "paused" for x in later.received)
            await operator.send(m.Stop())
            await ended(operator)

    with running_server(tmp_path) as server:
        asyncio.run(scenario(server))


def test_a_hand_moved_while_paused_does_not_jump_its_arm(tmp_path: Path) -> None:
    """The left grip held throughout: the hand moves 20 cm while the trial stands paused;
    after the resume the arm's target goes on from where it was, not 20 cm away."""
    settings = {"task": {"countdown_s": 0.0, "time_limit_s": 60.0}}

    async def held(operator: Client, z: float, count: int = 8) -> m.State:
        seq = 0
        for _ in range(count):
            seq = await operator.input(left=hand(pose=(0, 1.0, z, 1, 0, 0, 0), grip=1.0))
            await asyncio.sleep(0.03)
        state = await operator.wait_for(lambda x: isinstance(x, m.State) and x.input_seq >= seq)
        assert isinstance(state, m.State)
        return state

    async def scenario(server: RunningServer) -> None:
        async with client(server) as operator:
            await operator.hello()
            before = len(operator.received)
            assert isinstance(await start(operator, settings), m.SessionStarted)
            await event(operator, "trial_started", since=before)
            gripped = await held(operator, -0.3)
            assert gripped.following == (True, False)
            await operator.send(m.Pause(paused=True))
            await event(operator, "paused")
            for _ in range(10):  # the hand moves 20 cm forward while paused
                await operator.input(left=hand(pose=(0, 1.0, -0.5, 1, 0, 0, 0), grip=1.0))
                await asyncio.sleep(0.03)
            await operator.send(m.Pause(paused=False))
            await event(operator, "resumed")
            after = await held(operator, -0.5)
            assert after.following == (True, False)
            jump = math.dist(gripped.tcp_targets[0][:3], after.tcp_targets[0][:3])
            assert jump < 0.02, jump  # re-anchored where it was
            moved = await held(operator, -0.6)  # and follows the hand from there
            assert math.dist(after.tcp_targets[0][:3], moved.tcp_targets[0][:3]) > 0.07
            await operator.send(m.Stop())
            await ended(operator)

    with running_server(tmp_path) as server:
        asyncio.run(scenario(server))


async def measured(server: RunningServer, timeout: float = 30.0) -> dict[str, Any]:
    """The first seat's session's diagnostics once its figures are measured."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        sims = server.get_json("/api/diagnostics")["sims"]
        if sims and sims[0]["cores"] > 0:
            return dict(sims[0])
        await asyncio.sleep(0.5)
    raise TimeoutError("the session was never measured")


def test_a_start_waits_in_line_while_the_cores_budget_is_spent(tmp_path: Path) -> None:
    """With a budget of 0.05 cores, one running session leaves no room for a second: the
    second start is queued, told its position, and starts by itself once the first ends."""
    settings = {"task": {"countdown_s": 0.0, "time_limit_s": 60.0}}

    async def scenario(server: RunningServer) -> None:
        async with client(server) as first, client(server) as second:
            await first.hello()
            await second.hello()
            assert isinstance(await start(first, settings), m.SessionStarted)
            await second.send(m.StartSession(settings=FAST_SETTINGS))
            queued = await second.wait_for(lambda x: isinstance(x, m.Queued | m.SessionStarted))
            assert isinstance(queued, m.Queued), queued
            assert (queued.position, queued.waiting) == (1, 1)
            assert "position 1 of 1" in queued.message and "0.05" in queued.message
            assert server.seats.line.waiting == 1
            await second.send(m.StartSession(settings=FAST_SETTINGS))  # again: keeps its place
            again = await second.wait_for(lambda x: isinstance(x, m.Queued))
            assert isinstance(again, m.Queued) and (again.position, again.waiting) == (1, 1)
            assert server.seats.line.waiting == 1
            figures = await measured(server)
            # two sessions at the first's measured cost exceed the budget (an idle person's
            # session costs about 0.05 cores: held arms solve no IK), hence the line
            assert figures["real_time_factor"] > 0 and 2 * figures["cores"] > 0.05
            await first.send(m.Stop())
            await ended(first)
            started = await second.wait_for(lambda x: isinstance(x, m.SessionStarted), 30)
            assert isinstance(started, m.SessionStarted)
            assert server.seats.line.waiting == 0
            await second.send(m.Stop())
            await ended(second)

    with running_server(tmp_path, max_sessions=2, admit_cores=0.05) as server:
        asyncio.run(scenario(server))


def test_a_start_waits_while_a_running_session_is_below_the_real_time_needed(
    tmp_path: Path,
) -> None:
    """No paced session runs at 2x real time: once the first is measured, a second start
    waits, told why in words (the measured factor); a waiting client that leaves leaves
    the line."""
    settings = {"task": {"countdown_s": 0.0, "time_limit_s": 60.0}}

    async def scenario(server: RunningServer) -> None:
        async with client(server) as first:
            await first.hello()
            assert isinstance(await start(first, settings), m.SessionStarted)
            await measured(server)
            async with client(server) as second:
                await second.hello()
                await second.send(m.StartSession(settings=FAST_SETTINGS))
                queued = await second.wait_for(lambda x: isinstance(x, m.Queued))
                assert isinstance(queued, m.Queued)
                assert "x real time, below the 2.00x needed" in queued.message
            for _ in range(50):
                if server.seats.line.waiting == 0:
                    break
                await asyncio.sleep(0.1)
            assert server.seats.line.waiting == 0
            await first.send(m.Stop())
            await ended(first)

    with running_server(
        tmp_path, max_sessions=2, admit_min_real_time_factor=2.0, admit_cores=64.0
    ) as server:
        asyncio.run(scenario(server))

"""A person corrects a running driver over a real socket (issue 35): with ``driver =
"expert"`` the person watches, takes over at once without a jump, moves an arm, hands back,
and the expert goes on from there and delivers; the record says who drove every frame."""

from __future__ import annotations

import asyncio
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from tests.server.harness import FAST_SETTINGS, client, hand, running_server
from workcell.protocol import messages as m
from workcell.record.store import Store
from workcell.server.conductor import LINK_DROPPED
from workcell.task import events as ev

EXPERT: dict[str, Any] = {
    "driver": "expert",
    "seed": 3,
    "task": {"countdown_s": 0.0, "time_limit_s": 120.0},
}


def _state(message: object, taken_over: bool, after: float = 0.0) -> bool:
    return (
        isinstance(message, m.State)
        and message.hud is not None
        and message.hud.taken_over is taken_over
        and message.t_sim > after
    )


@pytest.mark.slow
def test_the_person_takes_over_from_the_expert_and_hands_back(tmp_path: Path) -> None:
    async def scenario() -> None:
        with running_server(tmp_path) as server:
            async with client(server) as operator, client(server) as spectator:
                await operator.hello()
                await spectator.hello(role="spectator")
                await operator.send(m.StartSession(settings=EXPERT))
                watching = await operator.wait_for(lambda x: _state(x, False, 1.0), 30.0)
                assert isinstance(watching, m.State) and watching.hud is not None
                assert watching.hud.driver == "expert"
                await spectator.send(m.TakeOver(reason="mine"))
                refused = await spectator.wait_for(lambda x: isinstance(x, m.Error))
                assert isinstance(refused, m.Error) and refused.code == "not_allowed"

                await operator.send(m.TakeOver(reason="  too slow  "))
                took = await operator.wait_for(lambda x: isinstance(x, ev.TookOver), 10.0)
                assert isinstance(took, ev.TookOver)
                assert (took.driver, took.reason, took.operator_id) == (
                    "expert",
                    "too slow",
                    "anonymous",
                )
                await operator.wait_for(lambda x: _state(x, True), 10.0)
                # the left grip held, the hand raised 12 cm: the left arm follows it up
                for k in range(40):
                    y = 1.0 + 0.003 * k
                    await operator.input(left=hand((0.0, y, -0.3, 1.0, 0.0, 0.0, 0.0), grip=1.0))
                    await asyncio.sleep(0.03)
                await operator.send(m.HandBack(reason="ok, yours"))
                back = await operator.wait_for(lambda x: isinstance(x, ev.HandedBack), 10.0)
                assert isinstance(back, ev.HandedBack) and back.reason == "ok, yours"
                await operator.wait_for(lambda x: _state(x, False), 10.0)
                ended = await operator.wait_for(lambda x: isinstance(x, m.SessionEnded), 240.0)
                assert isinstance(ended, m.SessionEnded)
                assert (ended.reason, ended.successes) == ("completed", 1)
        with Store.open(server.options.store, writer=False) as store:
            (trial,) = store.trials()
            assert (trial.driver, trial.outcome) == ("expert", "success")
            frames = store.frames(trial.trial_id)
            events = store.events(session_id=trial.session_id)
        flags = np.asarray(frames["intervention"])
        corrected = np.flatnonzero(flags == 1.0)
        assert set(flags.tolist()) == {0.0, 1.0} and len(corrected) >= 10
        first, last = int(corrected[0]), int(corrected[-1])
        assert len(corrected) == last - first + 1  # one take-over, one stretch of frames
        kinds = [
            (e.kind, e.payload.get("reason"))
            for e in events
            if e.kind in ("take_over", "hand_back")
        ]
        assert kinds == [("take_over", "too slow"), ("hand_back", "ok, yours")]
        took_at = next(e.t_sim for e in events if e.kind == "take_over")
        assert took_at is not None
        assert abs(float(frames["t_sim"][first]) - took_at) <= 0.051
        # no jump: the TCPs move smoothly across the take-over and the hand-back
        tcp = np.stack([frames[f"tcp_{s}_{a}"] for s in "lr" for a in "xyz"], axis=1)
        for at in (first, last + 1):
            step = np.abs(np.diff(tcp[at - 3 : at + 3], axis=0)).max()
            assert step < 0.02, (at, step)
        # the person raised the left arm while driving
        z = np.asarray(frames["tcp_l_z"])
        assert z[first : last + 1].max() - z[first] > 0.05
        # the person's device is recorded while they drive, not while the expert does
        grip = np.asarray(frames["grip_l"])
        assert grip[first + 5 : last - 2].min() == 1.0

    asyncio.run(scenario())


def test_a_session_the_person_drives_cannot_be_taken_over(tmp_path: Path) -> None:
    async def scenario() -> None:
        with running_server(tmp_path) as server:
            async with client(server) as operator:
                await operator.hello()
                await operator.send(m.TakeOver())
                refused = await operator.wait_for(lambda x: isinstance(x, m.Error))
                assert isinstance(refused, m.Error) and "no session is running" in refused.message
                await operator.send(m.StartSession(settings=FAST_SETTINGS))
                state = await operator.wait_for(lambda x: isinstance(x, m.State))
                assert isinstance(state, m.State) and state.hud is not None
                assert (state.hud.driver, state.hud.taken_over) == ("person", False)
                await operator.send(m.HandBack())
                refused = await operator.wait_for(lambda x: isinstance(x, m.Error))
                assert isinstance(refused, m.Error) and refused.code == "not_allowed"
                assert "driver = person" in refused.message
                await operator.send(m.Stop())
                await operator.wait_for(lambda x: isinstance(x, m.SessionEnded))
        with Store.open(server.options.store, writer=False) as store:
            (trial,) = store.trials()
            assert trial.driver == "person"
            assert set(np.asarray(store.frames(trial.trial_id)["intervention"]).tolist()) == {0.0}

    asyncio.run(scenario())


def test_a_bad_driver_is_refused_naming_what_is_allowed(tmp_path: Path) -> None:
    async def scenario() -> None:
        with running_server(tmp_path) as server:
            async with client(server) as operator:
                await operator.hello()
                await operator.send(m.StartSession(settings={"driver": "autopilot"}))
                rejected = await operator.wait_for(lambda x: isinstance(x, m.ConfigRejected))
                assert isinstance(rejected, m.ConfigRejected)
                (problem,) = rejected.problems
                assert problem.path == ("driver",) and problem.value == "autopilot"
                assert "person, expert or policy:PATH" in problem.message

    asyncio.run(scenario())


def test_a_policy_driver_that_is_not_there_refuses_the_start_in_one_line(tmp_path: Path) -> None:
    async def scenario() -> None:
        with running_server(tmp_path) as server:
            async with client(server) as operator:
                await operator.hello()
                missing = tmp_path / "no-such-policy"
                await operator.send(m.StartSession(settings={"driver": f"policy:{missing}"}))
                refused = await operator.wait_for(lambda x: isinstance(x, m.Error), 60)
                assert isinstance(refused, m.Error), refused
                assert str(missing) in refused.message and "\n" not in refused.message

    asyncio.run(scenario())


@pytest.mark.slow
def test_a_dropped_link_hands_back_and_a_reconnect_does_not_take_over_again(
    tmp_path: Path,
) -> None:
    async def scenario() -> None:
        with running_server(tmp_path, grace_s=10.0) as server:
            async with client(server) as spectator:
                await spectator.hello(role="spectator")
                async with client(server) as first:
                    token = (await first.hello()).resume_token
                    assert token is not None
                    await first.send(m.StartSession(settings=EXPERT))
                    await first.wait_for(lambda x: _state(x, False, 1.0), 30.0)
                    await first.send(m.TakeOver(reason="mine"))
                    await first.wait_for(lambda x: _state(x, True), 10.0)
                # the person's connection closed while they drove: the expert takes back over
                back = await spectator.wait_for(lambda x: isinstance(x, ev.HandedBack), 10.0)
                assert isinstance(back, ev.HandedBack)
                assert (back.reason, back.driver) == (LINK_DROPPED, "expert")
                watching = await spectator.wait_for(lambda x: _state(x, False), 10.0)
                assert isinstance(watching, m.State) and watching.hud is not None
                assert watching.hud.driver == "expert"
                assert server.conductor.session is not None  # within the grace: still running
                async with client(server) as again:
                    welcome = await again.hello("operator", token)
                    assert welcome.role == "operator"  # the seat comes back, not the controls
                    state = await again.wait_for(lambda x: isinstance(x, m.State), 10.0)
                    assert isinstance(state, m.State) and state.hud is not None
                    assert state.hud.taken_over is False
                    await again.send(m.TakeOver(reason="again"))  # taking over again works
                    await again.wait_for(lambda x: _state(x, True), 10.0)
                    await again.send(m.Stop())
                    ended = await again.wait_for(lambda x: isinstance(x, m.SessionEnded), 30.0)
                    assert isinstance(ended, m.SessionEnded)
                    assert ended.reason == "operator_stop"
        with Store.open(server.options.store, writer=False) as store:
            (trial,) = store.trials()
            events = store.events(session_id=trial.session_id)
        kinds = [
            (e.kind, e.payload.get("reason"))
            for e in events
            if e.kind in ("take_over", "hand_back")
        ]
        assert kinds == [("take_over", "mine"), ("hand_back", LINK_DROPPED), ("take_over", "again")]

    asyncio.run(scenario())

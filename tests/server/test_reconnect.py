"""A dropped operator resumes within the grace period; past it the trial is client_lost."""

from __future__ import annotations

import asyncio
import time
from pathlib import Path

from tests.server.harness import FAST_SETTINGS, client, running_server
from workcell.protocol import messages as m
from workcell.record.store import Store


def test_reconnect_within_the_grace_period_resumes_control(tmp_path: Path) -> None:
    async def scenario() -> None:
        with running_server(tmp_path, grace_s=2.0) as server:
            async with client(server) as first:
                welcome = await first.hello()
                token = welcome.resume_token
                assert token is not None and welcome.grace_s == 2.0
                await first.send(m.StartSession(settings=FAST_SETTINGS))
                started = await first.wait_for(lambda x: isinstance(x, m.SessionStarted))
                assert isinstance(started, m.SessionStarted)
            await asyncio.sleep(0.3)
            async with client(server) as intruder:  # no token: the seat stays reserved
                assert (await intruder.hello("operator")).role == "spectator"
            async with client(server) as guesser:  # nor a wrong one
                assert (await guesser.hello("operator", "é" * 30)).role == "spectator"
            async with client(server) as back:
                welcome = await back.hello("operator", token)
                assert welcome.role == "operator"
                assert welcome.session_id == started.session_id
                await asyncio.sleep(2.5)  # past the grace period: still running
                assert server.conductor.session is not None
                seq = await back.input()
                state = await back.wait_for(lambda x: isinstance(x, m.State) and x.input_seq == seq)
                assert isinstance(state, m.State)
                await back.send(m.Stop())
                ended = await back.wait_for(lambda x: isinstance(x, m.SessionEnded))
                assert isinstance(ended, m.SessionEnded) and ended.reason == "operator_stop"

    asyncio.run(scenario())


def test_past_the_grace_period_the_trial_ends_client_lost(tmp_path: Path) -> None:
    async def scenario() -> None:
        with running_server(tmp_path, grace_s=0.5) as server:
            async with client(server) as watcher:
                await watcher.hello("spectator")
                async with client(server) as operator:
                    token = (await operator.hello()).resume_token
                    await operator.send(m.StartSession(settings=FAST_SETTINGS))
                    await operator.wait_for(lambda x: isinstance(x, m.SessionStarted))
                dropped = time.monotonic()
                ended = await watcher.wait_for(lambda x: isinstance(x, m.SessionEnded))
                assert isinstance(ended, m.SessionEnded) and ended.reason == "client_lost"
                assert time.monotonic() - dropped >= 0.45
                async with client(server) as late:  # the old token is void; the seat is free
                    welcome = await late.hello("operator", token)
                    assert welcome.role == "operator" and welcome.resume_token != token
            with Store.open(server.options.store, writer=False) as store:
                (session,) = store.sessions()
                (trial,) = store.trials()
                assert trial.outcome == "interrupted"
                assert trial.interruption_reason == "client_lost"
                assert session.status == "interrupted"

    asyncio.run(scenario())

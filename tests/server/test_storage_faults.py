"""``workcell serve`` when recording fails under a live operator: the store writer process
is killed, or the disk fills up. The simulation stops within one hand-over (0.25 s of sim
time), the clients and the store agree on the reason (storage_error), the store
verifies, and the server carries on."""

from __future__ import annotations

import asyncio
import os
import signal
from pathlib import Path

import pytest

from tests.record.processes import writer_of
from tests.record.small_disk import small_disk
from tests.server.harness import FAST_SETTINGS, Client, RunningServer, client, running_server
from workcell.protocol import messages as m
from workcell.record import Store
from workcell.record.verify import verify_store
from workcell.task import events as ev

HAND_OVER_S = 0.25
"""Sim time between two hand-overs of frames to the store writer."""


async def _start(operator: Client) -> None:
    await operator.hello()
    await operator.send(m.StartSession(settings=FAST_SETTINGS))
    await operator.wait_for(lambda x: isinstance(x, m.SessionStarted))


def _ended_as_storage_error(server: RunningServer) -> str:
    """The store says storage_error too; returns the error the trial's event names."""
    store = server.options.store
    assert verify_store(store) == []
    with Store.open(store, writer=False) as reader:
        (session,) = reader.sessions()
        (trial,) = reader.trials()
        (event,) = [e for e in reader.events(trial.trial_id) if e.kind == "interruption"]
    assert session.status == "interrupted"
    assert (trial.outcome, trial.interruption_reason) == ("interrupted", "storage_error")
    return str(event.payload["error"])


def test_a_killed_writer_stops_the_session_within_one_hand_over(tmp_path: Path) -> None:
    async def scenario(server: RunningServer) -> tuple[float, m.SessionEnded, ev.TrialEnded]:
        async with client(server) as operator:
            await _start(operator)
            writer = writer_of(os.getpid())
            state = await operator.wait_for(lambda x: isinstance(x, m.State) and x.t_sim > 1.0)
            assert isinstance(state, m.State)
            os.kill(writer, signal.SIGKILL)
            last = state.t_sim
            while True:
                message = await operator.next(10.0)
                if isinstance(message, m.State):
                    last = message.t_sim
                if isinstance(message, m.SessionEnded):
                    (told,) = [x for x in operator.received if isinstance(x, ev.TrialEnded)]
                    return last - state.t_sim, message, told

    with running_server(tmp_path) as server:
        simulated, ended, told = asyncio.run(scenario(server))
        # the sim runs in real time: what it simulated after the kill is one hand-over at
        # most (plus a State period and the scheduling of a loaded machine)
        assert simulated <= HAND_OVER_S + 0.15, simulated
        error = _ended_as_storage_error(server)
        assert "the store writer process was killed (SIGKILL)" in error
        # the clients are told why, and the trial's time the store has
        assert ended.reason == "storage_error" and ended.detail == error
        assert told.interruption_reason == "storage_error"
        with Store.open(server.options.store, writer=False) as reader:
            (trial,) = reader.trials()
        assert told.elapsed_s == trial.elapsed_s
        assert server.get("/api/sessions")[0] == 200  # the server carries on


def test_a_full_disk_ends_the_session_as_storage_error(
    tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    async def scenario(server: RunningServer) -> m.Error:
        async with client(server) as operator:
            await _start(operator)
            ended = await operator.wait_for(lambda x: isinstance(x, m.SessionEnded), 120.0)
            assert isinstance(ended, m.SessionEnded) and ended.reason == "storage_error"
            assert f"the disk holding {disk} is full" in ended.detail  # the clients are told
            await operator.send(m.StartSession(settings=FAST_SETTINGS))  # the disk is full
            refused = await operator.wait_for(lambda x: isinstance(x, m.Error))
            assert isinstance(refused, m.Error)
            return refused

    disk = tmp_path / "disk"
    with small_disk(disk, 1 << 20), running_server(tmp_path, store=disk / "s.sqlite") as server:
        refused = asyncio.run(scenario(server))
        assert refused.code == "not_allowed"
        assert refused.message.startswith("start_session: store ")
        assert f"the disk holding {disk} is full" in refused.message
        error = _ended_as_storage_error(server)
        assert f"the disk holding {disk} is full" in error
        assert server.get("/api/sessions")[0] == 200
    logged = [r.getMessage() for r in caplog.records if r.name == "workcell.server.live"]
    assert len(logged) == 1 and error in logged[0]  # the server's log says why, in one line

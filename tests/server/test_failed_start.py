"""A session that fails to start, whatever fails (a setting, the shard folder, its process
dying), leaves its seat free: the operator hears one error over the same socket, and the
next start succeeds."""

from __future__ import annotations

import asyncio
import os
import signal
from multiprocessing.connection import Connection
from pathlib import Path
from typing import Any, ClassVar

import pytest

from tests.server.harness import FAST_SETTINGS, Client, RunningServer, client, running_server
from workcell.protocol import messages as m
from workcell.server.session_process import SessionProcess
from workcell.server.shards import shard_folder


async def _refused(operator: Client, settings: dict[str, Any]) -> m.Error | m.ConfigRejected:
    """Start with ``settings``; the refusal the operator hears (its socket stays open)."""
    await operator.send(m.StartSession(settings=settings))
    refusal = await operator.wait_for(lambda x: isinstance(x, m.Error | m.ConfigRejected))
    assert isinstance(refusal, m.Error | m.ConfigRejected)
    return refusal


async def _starts_again(server: RunningServer, operator: Client) -> None:
    """The seat is free: the same operator starts a session, and stops it."""
    assert not server.conductor.starting and server.seats.running == 0
    await operator.send(m.StartSession(settings=FAST_SETTINGS))
    started = await operator.wait_for(lambda x: isinstance(x, m.SessionStarted | m.Error))
    assert isinstance(started, m.SessionStarted), started
    await operator.send(m.Stop())
    ended = await operator.wait_for(lambda x: isinstance(x, m.SessionEnded), timeout=30)
    assert isinstance(ended, m.SessionEnded) and ended.reason == "operator_stop"


@pytest.mark.parametrize(
    "settings",
    [
        {"recording": {"sampling_rate_hz": 1e-310}},
        {"world": {"robot": {"ik_hz": 1e-310}}},
        {"world": {"robot": {"teleop_ik_hz": 1e-310}}},
    ],
)
def test_a_rate_too_small_to_divide_by_is_refused_and_frees_the_seat(
    tmp_path: Path, settings: dict[str, Any]
) -> None:
    async def scenario() -> None:
        with running_server(tmp_path) as server:
            async with client(server) as operator:
                await operator.hello()
                await _refused(operator, {**FAST_SETTINGS, **settings})
                await _starts_again(server, operator)

    asyncio.run(scenario())


def test_a_start_that_fails_past_the_settings_frees_the_seat(tmp_path: Path) -> None:
    """The shard folder cannot be made (a file holds its name): the operator hears why,
    and once the file is gone the same seat starts."""

    async def scenario() -> None:
        with running_server(tmp_path, max_sessions=2) as server:
            blocker = shard_folder(server.options.store)
            blocker.write_text("not a folder")
            async with client(server) as operator:
                assert (await operator.hello()).seat == "1"
                refusal = await _refused(operator, FAST_SETTINGS)
                assert isinstance(refusal, m.Error) and refusal.code == "not_allowed"
                assert refusal.message.startswith("start_session: the session failed to start")
                assert blocker.name in refusal.message
                blocker.unlink()
                await _starts_again(server, operator)

    asyncio.run(scenario())


class _KilledWhileStarting(SessionProcess):
    """The first session process is killed (as by the OOM killer) as soon as it is
    launched; the next ones run."""

    killed: ClassVar[list[int]] = []

    def _launch(self) -> Connection:
        conn = super()._launch()
        if not self.killed and self.pid is not None:
            os.kill(self.pid, signal.SIGKILL)
            self.killed.append(self.pid)
        return conn


def test_a_session_process_killed_while_starting_frees_the_seat(tmp_path: Path) -> None:
    _KilledWhileStarting.killed.clear()

    async def scenario() -> None:
        with running_server(tmp_path, launch=_KilledWhileStarting) as server:
            async with client(server) as operator:
                await operator.hello()
                refusal = await _refused(operator, FAST_SETTINGS)
                assert isinstance(refusal, m.Error)
                assert refusal.message == (
                    "start_session: the session's process died while starting (killed by SIGKILL)"
                )
                await _starts_again(server, operator)

    asyncio.run(scenario())

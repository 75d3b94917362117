"""The server runs on uvloop, as ``workcell serve`` configures it (issue 38: the standard
library's loop cost a live session latency and CPU; ``bench/README.md``)."""

from __future__ import annotations

import asyncio
from pathlib import Path

import uvloop

from tests.server.harness import client, running_server


def test_the_server_answers_its_clients_from_a_uvloop_event_loop(tmp_path: Path) -> None:
    async def scenario() -> None:
        with running_server(tmp_path) as server:
            async with client(server) as operator:
                welcome = await operator.hello()
                assert welcome.role == "operator"
                loop = server.conductor.loop
                assert isinstance(loop, uvloop.Loop), type(loop)
                assert not isinstance(asyncio.get_running_loop(), uvloop.Loop)  # the test's

    asyncio.run(scenario())

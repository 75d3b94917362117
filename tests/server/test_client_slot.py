"""A slow client gets the newest State, not a backlog; ordered messages keep their order."""

from __future__ import annotations

import asyncio
from typing import cast

from starlette.websockets import WebSocket

from workcell.protocol import messages as m
from workcell.server.client import Client


class SlowSocket:
    def __init__(self) -> None:
        self.sent: list[str] = []
        self.gate = asyncio.Event()

    async def send_text(self, text: str) -> None:
        await self.gate.wait()  # the network is slow until the test opens the gate
        self.sent.append(text)

    async def close(self, code: int = 1000, reason: str = "") -> None:
        self.sent.append(f"close {code}")


def test_stale_states_are_dropped_and_messages_are_not() -> None:
    async def scenario() -> None:
        socket = SlowSocket()
        client = Client(cast(WebSocket, socket), rate=100.0, burst=10)
        sender = asyncio.create_task(client.run_sender())
        client.send(m.Pong(t_client=1.0, t_server=2.0))
        for i in range(5):
            client.offer_state(f"state {i}")
            await asyncio.sleep(0)
        client.send(m.Pong(t_client=3.0, t_server=4.0))
        socket.gate.set()
        for _ in range(20):
            await asyncio.sleep(0.01)
        client.close()
        await asyncio.wait_for(sender, 1)
        states = [t for t in socket.sent if t.startswith("state")]
        pongs = [t for t in socket.sent if "pong" in t]
        assert len(pongs) == 2
        assert '"t_client":1.0' in pongs[0] and '"t_client":3.0' in pongs[1]
        assert states == ["state 4"]  # only the newest, though five were offered
        assert client.stats.states_dropped == 4 and client.stats.states_sent == 1

    asyncio.run(scenario())


def test_a_client_that_never_reads_is_cut_off() -> None:
    async def scenario() -> None:
        socket = SlowSocket()
        socket.gate.set()
        client = Client(cast(WebSocket, socket), rate=100.0, burst=10)
        for i in range(600):  # more ordered messages than may wait unsent
            client.send_text(f"message {i}")
        assert client.closed
        await asyncio.wait_for(client.run_sender(), 1)
        assert socket.sent[-1] == "close 4008"

    asyncio.run(scenario())

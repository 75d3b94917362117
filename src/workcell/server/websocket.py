"""The ``/ws`` endpoint: subprotocol check, hello, then messages until the client goes.

Every refused message (malformed, too large, not allowed, flooding) gets an Error reply
and a counter; the connection, the simulation and the other clients carry on.

Messages are read (and counted against the client's rate) as they arrive, also while the
client's session starts, which takes seconds: were they left unread until then, a client
driving at a normal rate would have them arrive all at once and be refused as a flood.
Inputs, pings and frame reports are handled while the session starts (an input then has
nothing to drive, as between sessions); any other message waits for the start, in order.
"""

from __future__ import annotations

import asyncio
import contextlib
import time
from collections.abc import Coroutine
from typing import Any, assert_never

from starlette.websockets import WebSocket, WebSocketDisconnect

from workcell.protocol import messages as m
from workcell.protocol.codec import ProtocolError, decode_client, encode
from workcell.server.auth import principal_of
from workcell.server.client import Client
from workcell.server.seats import Seats

CLOSE_PROTOCOL_MISMATCH = 4000
"""Close code for a client that does not speak this protocol version."""
OVERTAKE_A_START = (m.Input, m.Ping, m.FrameStats)
"""Messages handled while the client's session is starting (see the module)."""


async def refuse_version(websocket: WebSocket) -> None:
    """Accept (so a browser can read the reason), explain, close with code 4000."""
    offered = websocket.scope.get("subprotocols") or []
    await websocket.accept(subprotocol=offered[0] if offered else None)
    reason = f"protocol mismatch: this server speaks {m.SUBPROTOCOL}; reload the page"
    text = f"offered {', '.join(offered) or 'no subprotocol'}; {reason}"
    with contextlib.suppress(Exception):
        await websocket.send_text(encode(m.Error(code="protocol", message=text, fatal=True)))
    await websocket.close(code=CLOSE_PROTOCOL_MISMATCH, reason=reason[:120])


async def serve_client(websocket: WebSocket, seats: Seats) -> None:
    if m.SUBPROTOCOL not in (websocket.scope.get("subprotocols") or []):
        await refuse_version(websocket)
        return
    await websocket.accept(subprotocol=m.SUBPROTOCOL)
    options = seats.options
    client = Client(
        websocket, options.max_messages_per_s, options.burst, principal_of(websocket.scope)
    )
    seats.connected(client)
    sender = asyncio.create_task(client.run_sender())
    start: asyncio.Task[None] | None = None
    try:
        while not client.closed:
            received = await websocket.receive()
            if received["type"] == "websocket.disconnect":
                break
            raw = received.get("text")
            message = _admit(client, seats, raw if raw is not None else received.get("bytes"))
            if message is None:
                continue
            if start is not None and not isinstance(message, OVERTAKE_A_START):
                starting, start = start, None
                await starting
            slow = await _handle(client, seats, message)
            if slow is not None:
                start = asyncio.create_task(slow)
    except WebSocketDisconnect:
        pass
    finally:
        try:
            if start is not None:  # the seat hears of the disconnect once its session runs
                await start
        finally:
            client.close()
            seats.disconnected(client)
            sender.cancel()
            with contextlib.suppress(asyncio.CancelledError, Exception):
                await sender


def _admit(client: Client, seats: Seats, raw: str | bytes | None) -> m.ClientMessage | None:
    """The message ``raw`` decodes to, or None when it is refused (flood, malformed)."""
    client.stats.received += 1
    if not client.limiter.allow():
        client.refuse(
            "rate_limited",
            f"more than {seats.options.max_messages_per_s:g} messages/s: message dropped",
        )
        return None
    try:
        return decode_client(raw if raw is not None else b"")
    except ProtocolError as error:
        client.refuse(error.code, str(error), error.problem)
        return None


async def _handle(
    client: Client, seats: Seats, message: m.ClientMessage
) -> Coroutine[Any, Any, None] | None:
    """Handle ``message``; a session's start is returned to run beside later messages."""
    if isinstance(message, m.Ping):
        client.stats.rtt_ms = message.rtt_ms
        client.send(m.Pong(t_client=message.t_client, t_server=time.time()))
    elif isinstance(message, m.Hello):
        await seats.hello(client, message, client.principal)
    elif client.role is None or (conductor := seats.of(client)) is None:
        client.refuse("protocol", f"{message.type}: send hello first")
    elif isinstance(message, m.Input):
        conductor.input(client, message)
    elif isinstance(message, m.StartSession):
        return conductor.start_session(client, message)
    elif isinstance(message, m.Stop):
        conductor.stop(client, message)
    elif isinstance(message, m.Pause):
        conductor.pause(client, message)
    elif isinstance(message, m.Act):
        conductor.act(client, message)
    elif isinstance(message, m.TakeOver | m.HandBack):
        conductor.drive(client, message)
    elif isinstance(message, m.FrameStats):
        conductor.frame_stats(client, message)
    else:
        assert_never(message)
    return None

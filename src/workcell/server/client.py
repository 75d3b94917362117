"""One connected browser: its role, its outgoing messages and its counters.

Ordered messages (welcome, events, errors, ...) queue up; State does not: each client has
one "latest state" slot that a newer State overwrites, so a slow client gets the newest
poses rather than a growing backlog. One sender task per client drains both.
"""

from __future__ import annotations

import asyncio
import collections
import itertools
from dataclasses import dataclass, field

from starlette.websockets import WebSocket

from workcell.protocol.codec import encode
from workcell.protocol.messages import Error, ErrorCode, FieldProblem, Role, ServerMessage
from workcell.server.auth import ADMIN, Principal
from workcell.server.ratelimit import TokenBucket

MAX_QUEUED = 512
"""Ordered messages a client may have unsent before it is disconnected as too slow."""
MAX_ERRORS_PER_S = 20.0
"""Error replies per second; beyond this refusals are only counted."""

_ids = itertools.count(1)


@dataclass
class ClientStats:
    """Per-client diagnostics counters."""

    received: int = 0
    errors: dict[str, int] = field(default_factory=dict)
    """Refused messages by error code."""
    states_sent: int = 0
    states_dropped: int = 0
    """States overwritten before they could be sent (the client was slower)."""
    rtt_ms: float | None = None
    """The round-trip time the client last reported (its pings carry it)."""

    def refused(self, code: str) -> None:
        self.errors[code] = self.errors.get(code, 0) + 1


class Client:
    def __init__(
        self, websocket: WebSocket, rate: float, burst: int, principal: Principal = ADMIN
    ) -> None:
        self.id = next(_ids)
        self.websocket = websocket
        self.principal = principal
        """Who holds the token the connection carried (:mod:`workcell.server.auth`)."""
        self.role: Role | None = None
        """None until the client said hello."""
        self.stats = ClientStats()
        self.limiter = TokenBucket(rate, burst)
        self._error_replies = TokenBucket(MAX_ERRORS_PER_S, int(MAX_ERRORS_PER_S))
        self._queue: collections.deque[str] = collections.deque()
        self._state: str | None = None
        self._wake = asyncio.Event()
        self.closed = False

    def send(self, message: ServerMessage) -> None:
        self.send_text(encode(message))

    def send_text(self, text: str) -> None:
        if self.closed:
            return
        if len(self._queue) >= MAX_QUEUED:
            self.closed = True  # the sender task closes the socket
        self._queue.append(text)
        self._wake.set()

    @property
    def pending(self) -> int:
        """Ordered messages not yet sent."""
        return len(self._queue)

    def offer_state(self, text: str) -> None:
        """Make ``text`` the State to send next, dropping an unsent older one."""
        if self._state is not None:
            self.stats.states_dropped += 1
        self._state = text
        self._wake.set()

    def refuse(self, code: ErrorCode, message: str, problem: FieldProblem | None = None) -> None:
        """Count a refused message and tell the client (unless it floods us with them);
        ``problem`` is the refused value as data."""
        self.stats.refused(code)
        if self._error_replies.allow():
            self.send(Error(code=code, message=message, problem=problem))

    async def run_sender(self) -> None:
        """Send queued messages, then the latest State, until the client closes."""
        while not self.closed:
            await self._wake.wait()
            self._wake.clear()
            while self._queue and not self.closed:
                await self.websocket.send_text(self._queue.popleft())
            state, self._state = self._state, None
            if state is not None and not self.closed:
                await self.websocket.send_text(state)
                self.stats.states_sent += 1
        if len(self._queue) >= MAX_QUEUED:
            await self.websocket.close(code=4008, reason="too slow: messages piled up")

    def close(self) -> None:
        self.closed = True
        self._wake.set()

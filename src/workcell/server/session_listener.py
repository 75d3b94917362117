"""Carrying a live session's output from its simulation thread onto the server's loop."""

from __future__ import annotations

import asyncio
import contextlib
from typing import Protocol

from workcell.protocol import messages as m


class SessionOutput(Protocol):
    """Where the listener hands a session's output (the seat's conductor:
    :class:`workcell.server.conductor.Conductor`)."""

    @property
    def loop(self) -> asyncio.AbstractEventLoop | None: ...

    def broadcast_state(self, text: str) -> None: ...

    def broadcast_text(self, text: str) -> None: ...

    async def session_ended(self, ended: m.SessionEnded) -> None: ...


class SessionListener:
    """Carries a live session's output from the simulation thread onto the loop."""

    def __init__(self, conductor: SessionOutput) -> None:
        self.conductor = conductor
        loop = conductor.loop
        assert loop is not None
        self.loop = loop

    def state(self, text: str) -> None:
        with contextlib.suppress(RuntimeError):  # the loop closed: the server is gone
            self.loop.call_soon_threadsafe(self.conductor.broadcast_state, text)

    def message(self, text: str) -> None:
        with contextlib.suppress(RuntimeError):
            self.loop.call_soon_threadsafe(self.conductor.broadcast_text, text)

    def ended(self, message: m.SessionEnded) -> None:
        with contextlib.suppress(RuntimeError):
            asyncio.run_coroutine_threadsafe(self.conductor.session_ended(message), self.loop)

"""Where a relayed session's output goes: the seat's conductor, on the server's loop."""

from __future__ import annotations

import asyncio
from typing import Protocol

from workcell.protocol import messages as m


class SessionOutput(Protocol):
    """Where a session's output is handed (the seat's conductor:
    :class:`workcell.server.conductor.Conductor`), on its loop."""

    @property
    def loop(self) -> asyncio.AbstractEventLoop | None: ...

    def broadcast_state(self, text: str) -> None: ...

    def broadcast_text(self, text: str) -> None: ...

    async def session_ended(self, ended: m.SessionEnded) -> None: ...


class SessionListener:
    """A seat's output and the loop it runs on, for the
    :class:`~workcell.server.session_relay.RelayedSession` it starts: the loop serves the
    session's pipe and hands what the session says to the conductor
    (`src/workcell/server/child_link.py`)."""

    def __init__(self, conductor: SessionOutput) -> None:
        self.conductor = conductor
        loop = conductor.loop
        assert loop is not None
        self.loop = loop

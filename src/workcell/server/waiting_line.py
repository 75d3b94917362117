"""The line of session starts the machine has no headroom for yet (see
:mod:`workcell.server.admission`): each waiting operator hears ``queued`` with their
position and why, again whenever that changes, and their session starts by itself, first
come first served, once the rule admits one more. An operator who leaves (or whose seat
starts a session otherwise) leaves the line."""

from __future__ import annotations

import asyncio
import contextlib
from collections.abc import Callable, Coroutine
from dataclasses import dataclass
from typing import Any, Protocol

from workcell.protocol import messages as m
from workcell.server.admission import AdmissionRule, Measured
from workcell.server.client import Client

RETRY_S = 0.5
"""How often the head of the line is looked at again."""


class Startable(Protocol):
    """A seat whose start can wait (a :class:`~workcell.server.conductor.Conductor`)."""

    @property
    def busy(self) -> bool:
        """A session runs or starts at the seat."""

    def begin(self, client: Client, start: m.StartSession) -> Coroutine[Any, Any, None]: ...


@dataclass
class _Waiting:
    seat: Startable
    client: Client
    start: m.StartSession
    told: tuple[int, int, str] = (0, 0, "")


class WaitingLine:
    def __init__(self, rule: AdmissionRule, running: Callable[[], list[Measured | None]]) -> None:
        self.rule = rule
        self._running = running
        """Each running (or starting) session's figures, None for one not yet measured."""
        self._waiting: list[_Waiting] = []
        self._task: asyncio.Task[None] | None = None

    @property
    def waiting(self) -> int:
        return len(self._waiting)

    def position(self, client: Client) -> int | None:
        """``client``'s place in the line, from 1 (None: not waiting)."""
        for place, waiting in enumerate(self._waiting, start=1):
            if waiting.client is client:
                return place
        return None

    def admit(self, seat: Startable, client: Client, start: m.StartSession) -> bool:
        """True when ``seat`` may start now; else its start joins the line (``client``
        is told) and starts later by itself. A client already waiting keeps its place (with
        the settings of its latest start)."""
        for waiting in self._waiting:
            if waiting.client is client:
                waiting.start = start
                waiting.told = (0, 0, "")
                self._tell(self.rule.refuses(self._running()) or "others are waiting before you")
                return False
        why = self.rule.refuses(self._running())
        if why is None and not self._waiting:
            return True
        self._waiting.append(_Waiting(seat, client, start))
        self._tell(why or "others are waiting before you")
        if self._task is None or self._task.done():
            self._task = asyncio.create_task(self._serve())
        return False

    def leave(self, client: Client) -> None:
        if self._drop(client):
            self._tell(self.rule.refuses(self._running()) or "others are waiting before you")

    def close(self) -> None:
        self._waiting.clear()
        if self._task is not None:
            self._task.cancel()

    def _drop(self, client: Client) -> bool:
        before = len(self._waiting)
        self._waiting = [w for w in self._waiting if w.client is not client]
        return len(self._waiting) != before

    async def _serve(self) -> None:
        while self._waiting:
            await asyncio.sleep(RETRY_S)
            self._waiting = [w for w in self._waiting if not (w.client.closed or w.seat.busy)]
            if not self._waiting:
                return
            why = self.rule.refuses(self._running())
            if why is not None:
                self._tell(why)
                continue
            head = self._waiting.pop(0)
            self._tell("others are waiting before you")
            with contextlib.suppress(Exception):  # the seat tells its client what failed
                await head.seat.begin(head.client, head.start)

    def _tell(self, why: str) -> None:
        """Each waiting client its position, when it or the reason changed."""
        total = len(self._waiting)
        for place, waiting in enumerate(self._waiting, start=1):
            reason = why if place == 1 else f"{place - 1} start(s) wait before yours"
            told = (place, total, reason)
            if told == waiting.told:
                continue
            waiting.told = told
            message = (
                f"queued: position {place} of {total}; your session starts by itself when "
                f"the machine has room for it ({reason})"
            )
            waiting.client.send(m.Queued(position=place, waiting=total, message=message))

"""What the server says to a session's child, sent by a thread of its own.

A pipe (or an actor's socket) holds some 64 KiB. A child that stops reading it (stopped,
or hung in native code with its reading thread starved) would make the next send block,
and the server sends from its event loop, which serves every other session too: one
frozen simulation would freeze them all. :class:`PipeOutbox` takes each message at once
and hands it to the pipe from its own thread, so only that thread ever waits on a child.

While messages wait, a newer operator input replaces a waiting one: the child's operator
acts on the newest input at each control period anyway, so a frozen child's outbox holds
at most one input however long its operator keeps sending. (Messages wait only while the
child does not read; a child that reads gets every input, each sent as it comes.) Every
other message (actions, frame reports, stop) is kept, in order.
"""

from __future__ import annotations

import collections
import contextlib
import threading
from multiprocessing.connection import Connection
from typing import Any

MAX_WAITING = 1000
"""Messages other than inputs kept waiting for a child that does not read (the oldest
frame reports go first beyond it): a bound on what a frozen child can cost the server."""


class PipeOutbox:
    """Messages for ``conn``, sent in order by a thread of their own (see the module's
    docstring). :meth:`close` ends the thread; the connection stays the caller's."""

    def __init__(self, conn: Connection, name: str = "workcell-session-outbox") -> None:
        self._conn = conn
        self._waiting: collections.deque[tuple[Any, ...]] = collections.deque()
        self._ready = threading.Condition()
        self._closed = False
        self._thread = threading.Thread(target=self._run, name=name, daemon=True)
        self._thread.start()

    def put(self, message: tuple[Any, ...]) -> None:
        """Queue ``message``; never waits on the child."""
        with self._ready:
            if self._closed:
                return
            waiting = self._waiting
            if message[0] == "input" and waiting and waiting[-1][0] == "input":
                waiting[-1] = message  # the newer input replaces the one not yet sent
            else:
                if len(waiting) >= MAX_WAITING:
                    _drop_a_frame_report(waiting)
                waiting.append(message)
            self._ready.notify()

    @property
    def waiting(self) -> int:
        """Messages not yet handed to the pipe."""
        with self._ready:
            return len(self._waiting)

    def close(self) -> None:
        """Stop sending (what waits is dropped: the child is gone or going)."""
        with self._ready:
            self._closed = True
            self._waiting.clear()
            self._ready.notify()

    def _run(self) -> None:
        while True:
            with self._ready:
                while not self._waiting and not self._closed:
                    self._ready.wait()
                if self._closed:
                    return
                message = self._waiting.popleft()
            with contextlib.suppress(OSError, ValueError):  # the child is gone
                self._conn.send(message)


def _drop_a_frame_report(waiting: collections.deque[tuple[Any, ...]]) -> None:
    """Make room: the oldest frame report goes (figures for the record only), else the
    oldest message of any kind but a stop."""
    for index, message in enumerate(waiting):
        if message[0] == "frames":
            del waiting[index]
            return
    for index, message in enumerate(waiting):
        if message[0] != "stop":
            del waiting[index]
            return

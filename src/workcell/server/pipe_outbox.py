"""What waits for a session's child that does not read.

A child's socket holds some hundreds of KiB. A child that stops reading it (stopped, or
hung in native code) would make the server's writes pile up without end, and the server
writes from its event loop, which serves every other session too. Once the socket and
the transport's buffer are full (:mod:`~workcell.server.child_link`), messages wait in an
:class:`Outbox` instead, by its rule: a newer operator input replaces a waiting one (the
child's operator acts on the newest input at each control period anyway, so a frozen
child's outbox holds at most one input however long its operator keeps sending). Every
other message (actions, frame reports, stop) is kept, in order, up to :data:`MAX_WAITING`.
"""

from __future__ import annotations

import collections
from typing import Any

MAX_WAITING = 1000
"""Messages other than inputs kept waiting for a child that does not read (the oldest
frame reports go first beyond it): a bound on what a frozen child can cost the server."""


class Outbox:
    """Messages waiting for a child, in order, by the module's rule."""

    def __init__(self) -> None:
        self._waiting: collections.deque[tuple[Any, ...]] = collections.deque()

    def put(self, message: tuple[Any, ...]) -> None:
        waiting = self._waiting
        if message[0] == "input" and waiting and waiting[-1][0] == "input":
            waiting[-1] = message  # the newer input replaces the one not yet sent
            return
        if len(waiting) >= MAX_WAITING:
            _drop_a_frame_report(waiting)
        waiting.append(message)

    def pop(self) -> tuple[Any, ...]:
        """The oldest waiting message (IndexError when none waits)."""
        return self._waiting.popleft()

    def clear(self) -> None:
        self._waiting.clear()

    def __len__(self) -> int:
        return len(self._waiting)


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

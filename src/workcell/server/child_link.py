"""The server's end of a session child's pipe, served by the server's event loop.

A session's child (:func:`~workcell.server.session_child.run_child`, in a process or a Ray
actor) talks to the server over one stream socket with :mod:`multiprocessing.connection`'s
framing: each message a pickle, after its length as a 4-byte big-endian signed integer
(-1, then an 8-byte length, for a message of 2 GiB or more). The child reads and writes it
with a blocking :class:`~multiprocessing.connection.Connection`; the server reads and
writes it here, from its event loop, as an asyncio protocol on the socket: no thread per
session and no hand-over between threads for each State (at 16 sessions the 32 threads
this replaced cost the server as much CPU as its loop, `bench/README.md`).

Nothing here waits on a child. While the socket will not take more (a child that stopped
reading: stopped, or hung in native code), messages wait in an :class:`~workcell.server.
pipe_outbox.Outbox`, whose newest input replaces a waiting one, so a frozen child costs the
server at most the transport's buffer and one input however long its operator sends.
"""

from __future__ import annotations

import asyncio
import struct
from collections.abc import Callable
from multiprocessing.reduction import ForkingPickler
from typing import Any, cast

from workcell.server.pipe_outbox import Outbox

_LENGTH = struct.Struct("!i")
_LONG_LENGTH = struct.Struct("!Q")
_LONG = 0x7FFFFFFF
"""Longest message with a 4-byte length (multiprocessing.connection's rule)."""
WRITE_BUFFER_HIGH = 16 * 1024
"""Bytes the transport holds for a child before further messages wait in the outbox (where
a newer input replaces a waiting one): a few dozen inputs, on top of what the socket
itself holds."""


def frame(message: tuple[Any, ...]) -> bytes:
    """``message`` as :meth:`multiprocessing.connection.Connection.send` writes it."""
    body = bytes(ForkingPickler.dumps(message))
    if len(body) > _LONG:
        return _LENGTH.pack(-1) + _LONG_LENGTH.pack(len(body)) + body
    return _LENGTH.pack(len(body)) + body


class ChildLink(asyncio.Protocol):
    """One child's socket on the loop: each whole message received goes to ``on_message``
    (a tuple, as the child sent it), ``on_closed`` once the socket has closed (the child
    ended or died). :meth:`send` is for the loop's thread only."""

    def __init__(
        self,
        on_message: Callable[[tuple[Any, ...]], None],
        on_closed: Callable[[], None],
    ) -> None:
        self._on_message = on_message
        self._on_closed = on_closed
        self._transport: asyncio.Transport | None = None
        self._received = bytearray()
        self._outbox = Outbox()
        self._paused = False
        self._detached = False
        """The loop closed the transport while the child goes on."""
        self._ended = False
        """The child closed its end (or the socket failed)."""
        self.closed = False
        """The child's end has closed and :attr:`on_closed` was called."""

    # --- asyncio's side ---------------------------------------------------------------------

    def connection_made(self, transport: asyncio.BaseTransport) -> None:
        # a stream transport (uvloop's are not asyncio.Transport subclasses)
        self._transport = stream = cast(asyncio.Transport, transport)
        stream.set_write_buffer_limits(high=WRITE_BUFFER_HIGH)
        self.resume_writing()  # what was sent before the connection was made

    def data_received(self, data: bytes) -> None:
        received = self._received
        received += data
        start = 0
        while True:
            header = _LENGTH.size
            if len(received) - start < header:
                break
            (size,) = _LENGTH.unpack_from(received, start)
            if size == -1:
                header += _LONG_LENGTH.size
                if len(received) - start < header:
                    break
                (size,) = _LONG_LENGTH.unpack_from(received, start + _LENGTH.size)
            end = start + header + size
            if len(received) < end:
                break
            with memoryview(received) as view, view[start + header : end] as body:
                message = ForkingPickler.loads(body)
            start = end
            self._on_message(message)
        del received[:start]

    def eof_received(self) -> bool:
        self._ended = True
        return False  # the child's end closed: close ours

    def connection_lost(self, exc: Exception | None) -> None:
        """The transport closed: because the child's end closed or failed (``on_closed``),
        or because the loop closed its transports (the child goes on: the socket's other
        file descriptors, :class:`~workcell.server.session_relay.RelayedSession`'s, serve it
        from then on)."""
        self._transport = None
        if self.closed or not (self._ended or exc is not None):
            self._detached = True
            return
        self.closed = True
        self._outbox.clear()
        self._on_closed()

    def child_ended(self) -> None:
        """The child's end closed, seen by whoever reads the socket now the loop is gone."""
        self._ended = True
        self.connection_lost(None)

    def pause_writing(self) -> None:
        self._paused = True

    def resume_writing(self) -> None:
        self._paused = False
        transport = self._transport
        while not self._paused and self._outbox and transport is not None:
            transport.write(frame(self._outbox.pop()))

    # --- the server's side ------------------------------------------------------------------

    def send(self, message: tuple[Any, ...]) -> None:
        """Hand ``message`` to the socket, or queue it while the socket will not take more;
        never waits (dropped once the link has closed)."""
        transport = self._transport
        if self.closed or self._detached or (transport is not None and transport.is_closing()):
            return
        if transport is None or self._paused or self._outbox:
            self._outbox.put(message)  # until the connection is made, or the child reads
        else:
            transport.write(frame(message))

    @property
    def waiting(self) -> int:
        """Messages queued because the child does not read (beyond the transport's buffer)."""
        return len(self._outbox)

    @property
    def pending(self) -> bool:
        """Something written is not yet all in the socket (the transport's buffer or the
        outbox holds part of it)."""
        transport = self._transport
        buffered = transport is not None and transport.get_write_buffer_size() > 0
        return buffered or bool(self._outbox)

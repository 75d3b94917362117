"""Messages between a recording process and its store writer process: length-prefixed
pickles over a private pipe (both ends are this program; nothing else can write to it)."""

from __future__ import annotations

import os
import pickle
import select
import struct
from typing import IO, Any

_LENGTH = struct.Struct("<I")


def send(stream: IO[bytes], message: Any) -> None:
    """Write one message and flush it."""
    data = pickle.dumps(message, protocol=pickle.HIGHEST_PROTOCOL)
    stream.write(_LENGTH.pack(len(data)) + data)
    stream.flush()


def receive(stream: IO[bytes]) -> Any:
    """Read one message; raises EOFError when the other end has closed the pipe."""
    header = _read_exactly(stream, _LENGTH.size)
    (length,) = _LENGTH.unpack(header)
    return pickle.loads(_read_exactly(stream, length))


def _read_exactly(stream: IO[bytes], size: int) -> bytes:
    data = stream.read(size)
    if data is None or len(data) < size:
        raise EOFError("the other end of the pipe closed")
    return data


class MessageReader:
    """Messages from a pipe as they arrive, read without a thread: :meth:`wait` returns
    within ``timeout`` with the messages that are complete (none if nothing came)."""

    def __init__(self, fd: int) -> None:
        self._fd = fd
        self._buffer = bytearray()
        self._ended = False

    def wait(self, timeout: float) -> list[Any]:
        """The messages complete now, waiting up to ``timeout`` seconds for some; None
        last once the other end has closed the pipe (a message cut short is dropped)."""
        if self._ended:
            return [None]
        ready, _, _ = select.select([self._fd], [], [], timeout)
        if not ready:
            return []
        data = os.read(self._fd, 1 << 16)
        if not data:
            self._ended = True
            return [*self._complete(), None]
        self._buffer += data
        return self._complete()

    def _complete(self) -> list[Any]:
        messages = []
        at = 0
        buffer = self._buffer
        while len(buffer) - at >= _LENGTH.size:
            (length,) = _LENGTH.unpack_from(buffer, at)
            end = at + _LENGTH.size + length
            if end > len(buffer):
                break
            messages.append(pickle.loads(buffer[at + _LENGTH.size : end]))
            at = end
        del buffer[:at]
        return messages

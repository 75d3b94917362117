"""Messages between a recording process and its store writer process: length-prefixed
pickles over a private pipe (both ends are this program; nothing else can write to it),
how the writer is started, and how its failures are raised again on this side."""

from __future__ import annotations

import os
import pickle
import select
import struct
import subprocess
import sys
from pathlib import Path
from typing import IO, Any

from workcell.record.errors import RecordError, StorageError, StoreError

_LENGTH = struct.Struct("<I")

WRITER_MODULE = "workcell.recording.store_worker"
_ERRORS: dict[str, type[Exception]] = {
    "RecordError": RecordError,
    "StoreError": StoreError,
    "StorageError": StorageError,
}


def start_writer(
    path: Path, poll_s: float | None, key_file: Path | None
) -> subprocess.Popen[bytes]:
    """The writer process on the store at ``path``, its stdin and stdout the two pipes."""
    return subprocess.Popen(
        [
            sys.executable,
            "-m",
            WRITER_MODULE,
            str(path),
            *(() if poll_s is None else ("--poll", repr(poll_s))),
            *(() if key_file is None else ("--key", str(key_file))),
        ],
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
        start_new_session=True,  # a terminal's Ctrl-C goes to the recording process only
    )


def raised_error(kind: str, text: str) -> Exception:
    """The exception a failed call raised in the writer (sent as its class name and
    message), raised again in the recording process; an unknown class is a StorageError."""
    return _ERRORS.get(kind, StorageError)(text)


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

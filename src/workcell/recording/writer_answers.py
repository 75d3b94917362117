"""What a store's writer process says back (:mod:`workcell.recording.store_process`), read
on a thread of its own: the answers to the calls that wait for one, the failures of the
calls that did not, and which trials' ends the writer has written."""

from __future__ import annotations

import queue
import threading
from collections.abc import Callable
from typing import IO, Any

from workcell.recording.pipe_messages import raised_error, receive

Answer = tuple[Any, ...]


class WriterAnswers:
    """Reads ``stream`` until it ends; ``failed`` is told each failure of a call sent
    without waiting (as the error to raise)."""

    def __init__(self, stream: IO[bytes], failed: Callable[[Exception], None]) -> None:
        self._stream = stream
        self._failed = failed
        self._replies: queue.SimpleQueue[Answer | None] = queue.SimpleQueue()
        self.closed = False
        """The answer pipe reached its end: the writer has exited, or is exiting."""
        self._ends_sent: dict[int, str] = {}
        """Trials whose end was sent, by call id, until the writer answers."""
        self._ends_written: set[str] = set()
        self._thread: threading.Thread | None = None

    def start(self) -> None:
        self._thread = threading.Thread(target=self._read, name="store-writer-answers", daemon=True)
        self._thread.start()

    def join(self, timeout: float) -> None:
        if self._thread is not None:
            self._thread.join(timeout=timeout)

    def expect_end(self, call_id: int, trial_id: str) -> None:
        """The end of ``trial_id`` was sent as call ``call_id``: its answer says it is written."""
        self._ends_sent[call_id] = trial_id

    def end_written(self, trial_id: str) -> bool:
        """Whether the writer has written the end of ``trial_id``."""
        return trial_id in self._ends_written

    def reply(self, timeout: float) -> Answer | None:
        """The next waiting call's answer; None when the pipe ended first. Raises
        :class:`queue.Empty` after ``timeout`` seconds without one."""
        return self._replies.get(timeout=timeout)

    def _read(self) -> None:
        while True:
            try:
                answer = receive(self._stream)
            except (EOFError, OSError, ValueError):
                self.closed = True
                self._replies.put(None)
                return
            ended = None if answer[1] is None else self._ends_sent.pop(answer[1], None)
            if answer[1] is not None and ended is None:
                self._replies.put(answer)  # a waiting call's answer
            elif answer[0] == "error":  # a call sent without waiting failed
                self._failed(raised_error(answer[2], answer[3]))
            elif ended is not None:
                self._ends_written.add(ended)

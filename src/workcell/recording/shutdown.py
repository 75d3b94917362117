"""Stopping a recording cleanly on SIGINT and SIGTERM.

A signal handler must not write to the store itself: it could run between two statements
of a write. :class:`ShutdownSignals` only notes the request; the recording loop polls
:attr:`ShutdownSignals.requested` between frames and then ends the trial as
``interrupted``/``application_quit`` and the session as ``interrupted``. A second signal
while the loop has not stopped raises :class:`KeyboardInterrupt` (a stuck loop still dies;
the next writer recovers the trial as ``crash_recovered``).
"""

from __future__ import annotations

import signal
from types import FrameType, TracebackType
from typing import Any

SIGNALS = (signal.SIGINT, signal.SIGTERM)


class ShutdownSignals:
    """Context manager: while inside, SIGINT and SIGTERM set :attr:`requested`."""

    def __init__(self) -> None:
        self.requested: str | None = None
        """Name of the first signal received (``"SIGINT"``, ``"SIGTERM"``), else None."""
        self._previous: dict[int, Any] = {}

    def __enter__(self) -> ShutdownSignals:
        for number in SIGNALS:
            self._previous[number] = signal.signal(number, self._handle)
        return self

    def __exit__(
        self,
        kind: type[BaseException] | None,
        error: BaseException | None,
        traceback: TracebackType | None,
    ) -> None:
        for number, handler in self._previous.items():
            signal.signal(number, handler)
        self._previous.clear()

    def _handle(self, number: int, frame: FrameType | None) -> None:
        if self.requested is not None:
            raise KeyboardInterrupt
        self.requested = signal.Signals(number).name


def exit_status(signal_name: str) -> int:
    """128 + the signal's number: 130 after SIGINT, 143 after SIGTERM (the shells'
    convention for a process a signal ended)."""
    return 128 + signal.Signals[signal_name].value

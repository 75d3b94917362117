"""Fixed-rate pacing of the control loop against the wall clock, and stopping it.

Each control step has a due time on a fixed grid. The loop sleeps until the next one is
due; when it is late it runs steps back to back to catch up, but never more than
``max_catch_up_s`` behind: beyond that the grid is moved to now and the lost wall time is
counted in ``dropped_s`` (a stall never turns into a spiral of catching up). A
:class:`StopRequest` ends the loop from another thread, waking a pacer that sleeps.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable
from dataclasses import dataclass

from workcell.task.events import InterruptionReason


class StopRequest(threading.Event):
    """A request, from any thread, to end a session's running trial as interrupted with
    :attr:`reason` (the first request's reason counts)."""

    def __init__(self) -> None:
        super().__init__()
        self.reason: InterruptionReason | None = None

    def request(self, reason: InterruptionReason) -> None:
        if not self.is_set():
            self.reason = reason
            self.set()


@dataclass
class PacingStats:
    """Counters of the real-time loop (written by the loop, read by anyone)."""

    steps: int = 0
    late_steps: int = 0
    """Steps that started more than one period after they were due."""
    dropped_s: float = 0.0
    """Wall time given up because the loop fell more than the catch-up limit behind."""
    max_step_s: float = 0.0
    """Longest time one step took to compute."""
    started: float = 0.0
    last: float = 0.0

    @property
    def wall_s(self) -> float:
        return max(0.0, self.last - self.started)


class Pacer:
    """Paces steps of ``period`` seconds; :meth:`wait` before each, :meth:`done` after."""

    def __init__(
        self,
        period: float,
        max_catch_up_s: float,
        clock: Callable[[], float] = time.monotonic,
    ) -> None:
        self.period = period
        self.max_catch_up_s = max_catch_up_s
        self.clock = clock
        self.stats = PacingStats()
        self._due = clock()
        self.stats.started = self.stats.last = self._due
        self._step_start = self._due

    def wait(self, stop: threading.Event) -> bool:
        """Sleep until the next step is due; False when ``stop`` was set meanwhile."""
        delay = self._due - self.clock()
        if delay > 0 and stop.wait(delay):
            return False
        now = self.clock()
        if now - self._due > self.period:
            self.stats.late_steps += 1
        behind = now - self._due
        if behind > self.max_catch_up_s:
            self.stats.dropped_s += behind
            self._due = now
        self._step_start = now
        return not stop.is_set()

    def done(self) -> None:
        """The step that :meth:`wait` released has been computed."""
        now = self.clock()
        self.stats.steps += 1
        self.stats.max_step_s = max(self.stats.max_step_s, now - self._step_start)
        self.stats.last = now
        self._due += self.period

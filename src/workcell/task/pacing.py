"""Fixed-rate pacing of the control loop against the wall clock, and stopping it.

Each control step has a due time on a fixed grid. The loop sleeps until the next one is
due; when it is late it runs steps back to back to catch up, but never more than
``max_catch_up_s`` behind: beyond that the grid is moved to now and the lost wall time is
counted in ``dropped_s`` (a stall never turns into a spiral of catching up). A
:class:`StopRequest` ends the loop from another thread, waking a pacer that sleeps.

A loop that has work to do while it waits (a live session's child reads the server's
requests from its pipe, `src/workcell/server/session_child.py`) gives the pacer an
:data:`Idle`: the pacer then waits by calling it, and at least once before every step,
so what arrived while the loop computed is taken before the next period too.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable
from dataclasses import dataclass

from workcell.task.events import InterruptionReason

Idle = Callable[[float], None]
"""Wait up to the given seconds (0: do not wait), doing the work that arrives meanwhile;
may return early. The work may set the loop's :class:`StopRequest` or change its
:class:`PauseRequest`."""


class StopRequest(threading.Event):
    """A request, from any thread, to end a session's running trial as interrupted with
    :attr:`reason` (the first request's reason counts) and :attr:`note`, the words of
    whoever asked (an operator's or an admin's stop)."""

    def __init__(self) -> None:
        super().__init__()
        self.reason: InterruptionReason | None = None
        self.note = ""

    def request(self, reason: InterruptionReason, note: str = "") -> None:
        if not self.is_set():
            self.reason = reason
            self.note = note
            self.set()


class PauseRequest:
    """Whether the operator wants the running trial paused (set from any thread); the
    session loop waits in :meth:`wait_for_change` while it is."""

    def __init__(self) -> None:
        self._paused = False
        self._changed = threading.Condition()

    @property
    def paused(self) -> bool:
        return self._paused

    def set(self, paused: bool) -> None:
        with self._changed:
            self._paused = paused
            self._changed.notify_all()

    def wake(self) -> None:
        """Wake a waiting loop without changing anything (a stop was requested)."""
        with self._changed:
            self._changed.notify_all()

    def wait_for_change(self, timeout: float) -> None:
        with self._changed:
            self._changed.wait(timeout)


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
    paused_s: float = 0.0
    """Wall time the session stood paused (the operator's pause), not counted behind."""
    cpu_s: float = 0.0
    """CPU time of the session's process (every thread of it) at :attr:`last`."""
    recent_real_time_factor: float = 0.0
    """Simulated over wall time (pauses left out) across the latest
    :data:`RECENT_WINDOW_S` of wall time (0 before the first window ends)."""
    recent_cores: float = 0.0
    """The process's CPU time over wall time across the same window: how many cores the
    session used."""

    @property
    def wall_s(self) -> float:
        return max(0.0, self.last - self.started)


RECENT_WINDOW_S = 3.0
"""Wall seconds over which :attr:`PacingStats.recent_real_time_factor` is measured."""


class Pacer:
    """Paces steps of ``period`` seconds; :meth:`wait` before each, :meth:`done` after."""

    def __init__(
        self,
        period: float,
        max_catch_up_s: float,
        clock: Callable[[], float] = time.monotonic,
        idle: Idle | None = None,
    ) -> None:
        self.period = period
        self.idle = idle
        """How the pacer waits, when the loop has work to do meanwhile (see the module's
        docstring); None: it sleeps."""
        self.max_catch_up_s = max_catch_up_s
        self.clock = clock
        self.stats = PacingStats()
        self._due = clock()
        self.stats.started = self.stats.last = self._due
        self._step_start = self._due
        self._window = (self._due, 0, 0.0, time.process_time())
        """Where the recent window began: wall time, steps, paused time, CPU time."""

    def wait(self, stop: threading.Event) -> bool:
        """Sleep until the next step is due; False when ``stop`` was set meanwhile."""
        if self.idle is not None:
            if not self._idle_until_due(self.idle, stop):
                return False
        else:
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

    def _idle_until_due(self, idle: Idle, stop: threading.Event) -> bool:
        """Call ``idle`` until the next step is due (once at least); False when ``stop``
        was set meanwhile."""
        while True:
            left = self._due - self.clock()
            idle(max(left, 0.0))
            if stop.is_set():
                return False
            if left <= 0 or self.clock() >= self._due:
                return True

    def done(self) -> None:
        """The step that :meth:`wait` released has been computed."""
        now = self.clock()
        self.stats.steps += 1
        self.stats.max_step_s = max(self.stats.max_step_s, now - self._step_start)
        self.stats.last = now
        self._due += self.period
        self._measure(now)

    def skip(self, seconds: float) -> None:
        """The session stood paused for ``seconds``: the grid moves on by as much, and
        the time is counted as paused, not as dropped or late."""
        self._due += seconds
        self.stats.paused_s += seconds

    def _measure(self, now: float) -> None:
        began, steps, paused, cpu = self._window
        wall = now - began
        if wall < RECENT_WINDOW_S:
            return
        stats = self.stats
        cpu_now = time.process_time()
        running = wall - (stats.paused_s - paused)
        if running > 0:
            stats.recent_real_time_factor = (stats.steps - steps) * self.period / running
            stats.recent_cores = (cpu_now - cpu) / wall
        stats.cpu_s = cpu_now
        self._window = (now, stats.steps, stats.paused_s, cpu_now)

"""The server's side of a live session that runs somewhere else (a process of its own, a Ray
actor), talking to the server over one pipe.

:class:`RelayedSession` offers the server what :class:`~workcell.server.live.LiveSession`
offers (start, the operator's inputs, actions, frame reports, stop, the pacing counters)
and relays what the session says to the seat's conductor; the child at the other end of
the pipe runs :func:`~workcell.server.session_child.run_child`. Subclasses say only how
the child is started, waited for and killed, and how it ended: a dead child ends its
session ``error`` for its clients, naming what happened, and nothing else.

Once the seat has taken the session on (:meth:`RelayedSession.serve`), its pipe is served
by the server's event loop (:class:`~workcell.server.child_link.ChildLink`): what the
child says is dispatched on the loop as it arrives, and what the server says is written
from it, never waiting on the child.
"""

from __future__ import annotations

import asyncio
import contextlib
import dataclasses
import json
import logging
import operator
import os
import socket
import threading
from abc import ABC, abstractmethod
from dataclasses import dataclass
from multiprocessing.connection import Connection
from pathlib import Path
from typing import Any, ClassVar, Protocol

from workcell.errors import WorkcellError
from workcell.protocol.messages import FrameStats, Input, Scene, SessionEnded
from workcell.server.child_link import ChildLink, frame
from workcell.server.session_listener import SessionListener
from workcell.session.config import SessionConfig
from workcell.task import events as ev
from workcell.task.pacing import PacingStats
from workcell.teleop.rate import at_teleop_rate

logger = logging.getLogger(__name__)

START_TIMEOUT_S = 120.0
"""Longest a session's child may take to open its store and build its world."""
STOP_GRACE_S = 30.0
"""Longest a session's child may take to end once asked to stop (its trial closed, its
store flushed: well under a second normally) before the server kills it as stuck."""
KEPT_TO_THE_LAST_FRAMES = (
    "its trial is recorded up to the last frames written, and closed as interrupted "
    "(crash_recovered)"
)


pacing_values = operator.attrgetter(*(f.name for f in dataclasses.fields(PacingStats)))
"""A session's pacing counters as the plain tuple that goes down the pipe with each State
(a tuple of numbers pickles in a tenth of the time of the dataclass)."""


@dataclass(frozen=True)
class SessionArgs:
    """What the child needs to run its LiveSession."""

    config: SessionConfig
    store_path: Path
    state_hz: float
    max_catch_up_s: float
    key_file: Path | None


class SessionFactory(Protocol):
    """Makes the (not yet started) session a seat runs: :class:`~workcell.server.
    session_process.SessionProcess`, or :class:`~workcell.server.session_actor.RaySessions`
    for sessions in Ray actors."""

    def __call__(self, args: SessionArgs, listener: SessionListener) -> RelayedSession: ...


class RemoteOperator:
    """The server's side of the child's teleoperator: the input ordering rule is kept
    here, so an old input is refused at once, as in one process."""

    def __init__(self, send: Any) -> None:
        self._send = send
        self._last_seq = -1
        self._lock = threading.Lock()

    def submit(self, message: Input) -> bool:
        with self._lock:
            if message.seq <= self._last_seq:
                return False
            self._last_seq = message.seq
        self._send(("input", message))
        return True

    def new_link(self) -> None:
        with self._lock:
            self._last_seq = -1
        self._send(("new_link",))


class RelayedSession(ABC):
    """Start with :meth:`start`, which returns once the session is recording (or raises)."""

    kind: ClassVar[str]
    """What the child is, in messages: "the session's {kind} died (...)"."""

    def __init__(self, args: SessionArgs, listener: SessionListener) -> None:
        self.config = at_teleop_rate(args.config)
        """The session as it runs: at the control rate a person drives at."""
        self.args = args
        self.session_id = ""
        self.scene: Scene | None = None
        self.operator = RemoteOperator(self._send)
        self._pacing = PacingStats()
        self._ended = False
        self._results: list[tuple[str, int]] = []
        """(outcome, score) of each trial the child reported ended."""
        self._output = listener.conductor
        self._loop = listener.loop
        self._conn: Connection | None = None
        """The child's pipe between :meth:`start` and :meth:`serve`."""
        self._link: ChildLink | None = None
        self._socket: socket.socket | None = None
        """The server's end of the child's pipe, once the loop serves it."""
        self._closed = threading.Event()
        """The pipe has closed (the child ended or died) and the loop has seen it."""
        self._drain: threading.Thread | None = None
        """Reads the pipe when the loop has closed before the child ended."""
        self._tasks: set[asyncio.Task[None]] = set()
        self._overdue = ""
        """Why the server killed the child, when it did (it did not stop when asked)."""
        self._stop_timer: threading.Timer | None = None

    # --- how the child runs (the subclass's part) -------------------------------------------

    @abstractmethod
    def _launch(self) -> Connection:
        """Start the child; the server's end of its pipe (raises WorkcellError)."""

    @abstractmethod
    def _reap(self, timeout: float | None) -> None:
        """Wait up to ``timeout`` s for the child to end (and finish with it)."""

    @abstractmethod
    def kill(self) -> None:
        """End the child at once, as a crash would (tests, a stuck simulation)."""

    @property
    @abstractmethod
    def running(self) -> bool:
        """The child is alive."""

    @property
    @abstractmethod
    def pid(self) -> int | None:
        """The child's process id (None before it started)."""

    @abstractmethod
    def _exit(self) -> str:
        """How the child ended ("killed by SIGKILL"), or "still running"."""

    def _kept(self) -> str:
        """What is left of the record of a session whose child died."""
        return KEPT_TO_THE_LAST_FRAMES

    # --- the session ------------------------------------------------------------------------

    def start(self) -> None:
        """Start the child; return once its session records, or raise what stopped it.
        Blocking: call it from a thread other than the loop's; then :meth:`serve`."""
        conn = self._launch()
        if not conn.poll(START_TIMEOUT_S):
            self.kill()
            raise WorkcellError(f"the session's {self.kind} did not start in {START_TIMEOUT_S:g} s")
        try:
            first = conn.recv()
        except (EOFError, OSError):
            self._reap(5)
            raise WorkcellError(
                f"the session's {self.kind} died while starting ({self._exit()})"
            ) from None
        if first[0] == "failed":
            self._reap(10)
            conn.close()
            raise WorkcellError(first[1])
        _, self.session_id, self.scene = first
        self._conn = conn

    async def serve(self) -> None:
        """From now on the loop serves the child's pipe (a stream socket): call it on the
        loop once the seat has taken the session on and told its clients, so nothing the
        session says reaches them before it (what it said meanwhile waited in the pipe).
        A descriptor of the socket is kept for when the loop is gone (uvloop closes its
        transports with it)."""
        conn, self._conn = self._conn, None
        if conn is None or self._link is not None:
            return
        served = socket.socket(fileno=os.dup(conn.fileno()))
        self._socket = socket.socket(fileno=os.dup(conn.fileno()))
        conn.close()
        self._link = link = ChildLink(self._take, self._link_closed)
        await self._loop.connect_accepted_socket(lambda: link, served)

    def request_action(self, action: ev.OperatorAction, source: ev.ActionSource) -> None:
        self._send(("act", action, source))

    def request_driving(self, person: bool, reason: str = "") -> None:
        self._send(("drive", person, reason))

    def report_frames(self, stats: FrameStats) -> None:
        self._send(("frames", stats))

    def request_pause(self, paused: bool) -> None:
        self._send(("pause", paused))

    def request_stop(self, reason: ev.InterruptionReason, note: str = "") -> None:
        """Ask the child to end its trial as ``reason`` (``note``: the words of whoever
        asked, recorded); a child that has not ended
        :data:`STOP_GRACE_S` later (stopped, hung in native code) is killed, which ends
        its session ``error`` as a crash does."""
        self._send(("stop", reason, note))
        if self._stop_timer is None and self._link is not None:
            self._stop_timer = threading.Timer(STOP_GRACE_S, self._stop_overdue)
            self._stop_timer.daemon = True
            self._stop_timer.start()

    def _stop_overdue(self) -> None:
        if self._ended or not self.running:
            return
        self._overdue = (
            f"it did not end within {STOP_GRACE_S:g} s of being asked to stop, so the "
            "server killed it"
        )
        logger.warning("session %s: %s", self.session_id, self._overdue)
        self.kill()

    def join(self, timeout: float | None = None) -> bool:
        """Wait until the child has ended and closed its store, and its pipe has closed
        (not from the loop's thread, which sees the pipe close)."""
        if not self._loop.is_running():
            self._drain_without_loop()
        self._reap(timeout)
        if self._link is not None:
            self._closed.wait(timeout)
        return not self.running

    @property
    def pacing(self) -> PacingStats:
        return self._pacing

    @property
    def unsent(self) -> int:
        """Messages for the child not yet handed to its pipe (more than one or two only
        while the child does not read)."""
        return 0 if self._link is None else self._link.waiting

    @property
    def outcomes(self) -> tuple[str, ...]:
        """The outcome of each trial that has ended so far."""
        return tuple(outcome for outcome, _ in self._results)

    # --- the server side of the pipe --------------------------------------------------------

    def _send(self, message: tuple[Any, ...]) -> None:
        """Hand ``message`` to the child's pipe; never waits on the child (see
        :mod:`~workcell.server.child_link`). From any thread: the loop writes it."""
        link = self._link
        if link is None:
            return
        if _running_loop() is self._loop:
            link.send(message)
        elif self._loop.is_running():
            with contextlib.suppress(RuntimeError):  # closed meanwhile
                self._loop.call_soon_threadsafe(link.send, message)
        else:
            self._send_without_loop(message)

    def _take(self, message: tuple[Any, ...]) -> None:
        """One message from the child (on the loop; in the drain once the loop is gone,
        when nobody is left to hear it)."""
        kind, *body = message
        if kind == "state":
            self._pacing = PacingStats(*body[1])
            if self._loop.is_running():
                self._output.broadcast_state(body[0])
        elif kind == "message":
            self._tally(body[0])
            if self._loop.is_running():
                self._output.broadcast_text(body[0])
        elif kind == "scene":
            self.scene = body[0]
        elif kind == "log":  # the child's log, in the server's
            logging.getLogger(body[1]).log(body[0], "%s", body[2])
        elif kind == "ended":
            self._ended = True
            self._tell_ended(body[0])

    def _link_closed(self) -> None:
        """The child's pipe closed (on the loop, or in the drain once the loop is gone):
        a child that closed it without saying it ended died."""
        if self._socket is not None:
            self._socket.close()
        self._closed.set()
        if self._stop_timer is not None:
            self._stop_timer.cancel()
        if self._ended:
            return
        if not self._loop.is_running():
            self._reap(5)
            self._died()
            return
        self._hold_task(self._loop.create_task(self._end_died()))

    async def _end_died(self) -> None:
        await asyncio.to_thread(self._reap, 5)
        await self._output.session_ended(self._died())

    def _tell_ended(self, ended: SessionEnded) -> None:
        if self._loop.is_running():
            self._hold_task(self._loop.create_task(self._output.session_ended(ended)))

    def _hold_task(self, task: asyncio.Task[None]) -> None:
        """Hold ``task`` until it is done (the loop keeps only weak references)."""
        self._tasks.add(task)
        task.add_done_callback(self._tasks.discard)

    # --- when the loop is gone before the child ---------------------------------------------

    def _send_without_loop(self, message: tuple[Any, ...]) -> None:
        """The loop has stopped (the server is stopping outside it): write ``message``
        straight to the pipe, unless part of an earlier message still waits in the loop's
        buffer (a child that stopped reading: it is killed after the stop's grace)."""
        sock, link = self._socket, self._link
        if sock is None or link is None or link.closed or link.pending:
            return
        with contextlib.suppress(OSError):
            sock.settimeout(STOP_GRACE_S)
            sock.sendall(frame(message))

    def _drain_without_loop(self) -> None:
        """The loop has stopped: read the child's pipe in a thread until it closes, so a
        child still saying things (its States, its last log lines) ends undisturbed."""
        sock, link = self._socket, self._link
        if sock is None or link is None or link.closed or self._drain is not None:
            return

        def drain() -> None:
            with contextlib.suppress(OSError):
                sock.settimeout(None)
                while data := sock.recv(1 << 16):
                    link.data_received(data)
            link.child_ended()

        self._drain = threading.Thread(target=drain, name="workcell-session-drain", daemon=True)
        self._drain.start()

    def _tally(self, text: str) -> None:
        if '"trial_ended"' in text:
            event = json.loads(text)
            if event.get("kind") == "trial_ended":
                self._results.append((event["outcome"], int(event["score"])))

    def _died(self) -> SessionEnded:
        how = self._exit()
        if self._overdue:
            how = f"{self._overdue}: {how}"
        logger.warning("session %s: its %s died (%s)", self.session_id, self.kind, how)
        return SessionEnded(
            session_id=self.session_id,
            reason="error",
            trials=len(self._results),
            successes=sum(outcome == "success" for outcome, _ in self._results),
            total_score=sum(score for _, score in self._results),
            detail=f"the session's {self.kind} died ({how}); {self._kept()}",
        )


def _running_loop() -> asyncio.AbstractEventLoop | None:
    """The loop running in this thread, if any."""
    try:
        return asyncio.get_running_loop()
    except RuntimeError:
        return None

"""A live session in a process of its own: what lets one server run many sessions on all
its cores, and keeps a session whose simulation dies (a crash in native code, a kill) from
taking the server or any other session with it.

:class:`SessionProcess` offers the server what :class:`~workcell.server.live.LiveSession`
offers (start, the operator's inputs, actions, frame reports, stop, the pacing counters);
the child runs a LiveSession and talks to the server over one pipe (its log records too:
they are logged in the server as its own). Processes start from
a fork server that has imported the simulation once, so a session starts in well under a
second. When the child dies, the session ends ``error`` for its clients, naming the exit;
its trial stays open in its store and is closed ``interrupted`` (``crash_recovered``) when
the store is next opened for writing (the shard's merge, for a server with several seats).
"""

from __future__ import annotations

import contextlib
import json
import logging
import multiprocessing
import signal
import threading
from dataclasses import dataclass
from multiprocessing.connection import Connection
from multiprocessing.context import ForkServerContext
from pathlib import Path
from typing import Any

from workcell.errors import WorkcellError
from workcell.protocol.messages import FrameStats, Input, Scene, SessionEnded
from workcell.server.live import LiveSession, SessionListener
from workcell.session.config import SessionConfig
from workcell.task import events as ev
from workcell.task.pacing import PacingStats
from workcell.teleop.rate import at_teleop_rate

logger = logging.getLogger(__name__)

START_TIMEOUT_S = 120.0
"""Longest a session's process may take to open its store and build its world."""
_context: ForkServerContext | None = None


def _processes() -> ForkServerContext:
    """The fork-server context, its server preloaded with the simulation's modules."""
    global _context  # noqa: PLW0603 - one fork server per server process, made on first use
    if _context is None:
        context = multiprocessing.get_context("forkserver")
        context.set_forkserver_preload([__name__])
        _context = context
    return _context


@dataclass(frozen=True)
class _SessionArgs:
    """What the child needs to run its LiveSession."""

    config: SessionConfig
    store_path: Path
    state_hz: float
    max_catch_up_s: float
    key_file: Path | None


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


class SessionProcess:
    """Start with :meth:`start`, which returns once the session is recording (or raises)."""

    def __init__(
        self,
        config: SessionConfig,
        store_path: Path,
        listener: SessionListener,
        state_hz: float = 60.0,
        max_catch_up_s: float = 0.25,
        *,
        key_file: Path | None = None,
    ) -> None:
        self.config = at_teleop_rate(config)
        """The session as it runs: at the control rate a person drives at."""
        self.listener = listener
        self.session_id = ""
        self.scene: Scene | None = None
        self.operator = RemoteOperator(self._send)
        self._pacing = PacingStats()
        self._ended = False
        self._results: list[tuple[str, int]] = []
        """(outcome, score) of each trial the child reported ended."""
        self._send_lock = threading.Lock()
        context = _processes()
        self._conn, child_conn = context.Pipe()
        self._process = context.Process(
            target=_child,
            args=(child_conn, _SessionArgs(config, store_path, state_hz, max_catch_up_s, key_file)),
            name="workcell-session",
            daemon=True,
        )
        self._child_conn = child_conn
        self._reader = threading.Thread(
            target=self._read, name="workcell-session-pipe", daemon=True
        )

    @property
    def pid(self) -> int | None:
        return self._process.pid

    def start(self) -> None:
        """Start the process; return once its session records, or raise what stopped it."""
        self._process.start()
        self._child_conn.close()
        if not self._conn.poll(START_TIMEOUT_S):
            self._process.kill()
            raise WorkcellError(f"the session's process did not start in {START_TIMEOUT_S:g} s")
        try:
            first = self._conn.recv()
        except (EOFError, OSError):
            self._process.join(5)
            raise WorkcellError(
                f"the session's process died while starting ({self._exit()})"
            ) from None
        if first[0] == "failed":
            self._process.join(10)
            raise WorkcellError(first[1])
        _, self.session_id, self.scene = first
        self._reader.start()

    def request_action(self, action: ev.OperatorAction, source: ev.ActionSource) -> None:
        self._send(("act", action, source))

    def report_frames(self, stats: FrameStats) -> None:
        self._send(("frames", stats))

    def request_stop(self, reason: ev.InterruptionReason) -> None:
        self._send(("stop", reason))

    def join(self, timeout: float | None = None) -> bool:
        self._process.join(timeout)
        if self._reader.is_alive():
            self._reader.join(timeout)
        return not self._process.is_alive()

    @property
    def running(self) -> bool:
        return self._process.is_alive()

    @property
    def pacing(self) -> PacingStats:
        return self._pacing

    @property
    def outcomes(self) -> tuple[str, ...]:
        """The outcome of each trial that has ended so far."""
        return tuple(outcome for outcome, _ in self._results)

    def kill(self) -> None:
        """End the process at once, as a crash would (tests, a stuck simulation)."""
        self._process.kill()

    # --- the server side of the pipe --------------------------------------------------------

    def _send(self, message: tuple[Any, ...]) -> None:
        with self._send_lock, contextlib.suppress(OSError, ValueError):  # the child is gone
            self._conn.send(message)

    def _read(self) -> None:
        """Carry the child's output to the listener until the pipe closes."""
        while True:
            try:
                kind, *body = self._conn.recv()
            except (EOFError, OSError):
                break
            if kind == "state":
                self._pacing = body[1]
                self.listener.state(body[0])
            elif kind == "message":
                self._tally(body[0])
                self.listener.message(body[0])
            elif kind == "scene":
                self.scene = body[0]
            elif kind == "log":  # the child's log, in the server's
                logging.getLogger(body[1]).log(body[0], "%s", body[2])
            elif kind == "ended":
                self._ended = True
                self.listener.ended(body[0])
        if not self._ended:
            self._process.join(5)
            self.listener.ended(self._died())
        with contextlib.suppress(OSError):
            self._conn.close()

    def _tally(self, text: str) -> None:
        if '"trial_ended"' in text:
            event = json.loads(text)
            if event.get("kind") == "trial_ended":
                self._results.append((event["outcome"], int(event["score"])))

    def _died(self) -> SessionEnded:
        logger.warning("session %s: its process died (%s)", self.session_id, self._exit())
        return SessionEnded(
            session_id=self.session_id,
            reason="error",
            trials=len(self._results),
            successes=sum(outcome == "success" for outcome, _ in self._results),
            total_score=sum(score for _, score in self._results),
            detail=f"the session's process died ({self._exit()}); its trial is recorded up "
            "to the last frames written, and closed as interrupted (crash_recovered)",
        )

    def _exit(self) -> str:
        code = self._process.exitcode
        if code is None:
            return "still running"
        if code < 0:
            return f"killed by {signal.Signals(-code).name}"
        return f"exit code {code}"


# --- the child --------------------------------------------------------------------------------


class _PipeListener:
    """The child's listener: everything goes down the pipe (from the simulation thread)."""

    def __init__(self, conn: Connection) -> None:
        self.conn = conn
        self.lock = threading.Lock()
        self.live: LiveSession | None = None
        self._scene: Scene | None = None
        self._held: list[tuple[Any, ...]] | None = []
        """What the session said before the server heard it is ready (None: since)."""

    def send(self, message: tuple[Any, ...]) -> None:
        with self.lock, contextlib.suppress(OSError, ValueError):  # the server is gone
            if self._held is not None:
                self._held.append(message)
            else:
                self.conn.send(message)

    def first(self, message: tuple[Any, ...]) -> None:
        """``message`` ("ready" or "failed"), then whatever was held back."""
        with self.lock, contextlib.suppress(OSError, ValueError):
            held, self._held = self._held or [], None
            for item in (message, *held):
                self.conn.send(item)

    def state(self, text: str) -> None:
        live = self.live
        self.send(("state", text, live.pacing if live is not None else PacingStats()))

    def message(self, text: str) -> None:
        live = self.live
        if live is not None and live.scene is not self._scene:  # a new scene comes first
            self._scene = live.scene
            if self._scene is not None:
                self.send(("scene", self._scene))
        self.send(("message", text))

    def ended(self, message: SessionEnded) -> None:
        self.send(("ended", message))


class _PipeLogHandler(logging.Handler):
    """The child's log records go to the server, which logs them as its own."""

    def __init__(self, listener: _PipeListener) -> None:
        super().__init__(logging.INFO)
        self.listener = listener

    def emit(self, record: logging.LogRecord) -> None:
        text = record.getMessage()
        if record.exc_info:
            text += "\n" + logging.Formatter().formatException(record.exc_info)
        self.listener.send(("log", record.levelno, record.name, text))


def _child(conn: Connection, args: _SessionArgs) -> None:
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # the server decides when a session stops
    listener = _PipeListener(conn)
    root = logging.getLogger()
    root.handlers[:] = [_PipeLogHandler(listener)]
    root.setLevel(logging.INFO)
    live = LiveSession(
        args.config, args.store_path, listener, args.state_hz, args.max_catch_up_s,
        key_file=args.key_file,
    )  # fmt: skip
    listener.live = live
    try:
        live.start()
    except BaseException as error:  # told to the server, which refuses the start
        message = str(error) if isinstance(error, WorkcellError) else f"the server failed: {error}"
        listener.first(("failed", message))
        return
    listener.first(("ready", live.session_id, live.scene))
    commands = threading.Thread(target=_obey, args=(conn, live), daemon=True)
    commands.start()
    live.join()  # the session ended: its end went down the pipe, which closes on exit


def _obey(conn: Connection, live: LiveSession) -> None:
    """Apply the server's requests until the pipe closes; a closed pipe (the server died)
    ends the trial as ``application_quit``."""
    while True:
        try:
            kind, *body = conn.recv()
        except (EOFError, OSError):
            live.request_stop("application_quit")
            return
        if kind == "input":
            live.operator.submit(body[0])
        elif kind == "new_link":
            live.operator.new_link()
        elif kind == "act":
            live.request_action(body[0], body[1])
        elif kind == "frames":
            live.report_frames(body[0])
        elif kind == "stop":
            live.request_stop(body[0])

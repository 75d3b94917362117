"""The child's side of a relayed session (:mod:`workcell.server.session_relay`): a
LiveSession whose output goes down the pipe to the server, and which obeys what the server
sends up it. The same body runs in a session's process and in a session's Ray actor.

The pipe carries tuples. From the server: ``("input", Input)``, ``("new_link",)``,
``("act", action, source)``, ``("frames", FrameStats)``, ``("pause", paused)``,
``("drive", person, reason)`` (take over or hand back),
``("stop", reason, note)``. From the
child: first ``("ready", session_id, scene)`` or ``("failed", message)``, then
``("state", text, pacing)`` (the pacing counters as a tuple: ``pacing_values``),
``("scene", scene)``, ``("message", text)``, ``("log", level, logger, text)`` and last
``("ended", SessionEnded)``.

The simulation thread itself reads what the server sends, while it waits for its next
control period (:class:`_Obedience`, the pacer's :data:`~workcell.task.pacing.Idle`): no
thread of its own wakes for each input, and nothing the server asks waits for more than
one control period. Once the session has ended, a thread reads on until the server
closes its end.
"""

from __future__ import annotations

import contextlib
import logging
import select
import signal
import threading
import time
from multiprocessing.connection import Connection
from typing import Any

from workcell.errors import WorkcellError
from workcell.protocol.messages import Scene, SessionEnded
from workcell.server.live import LiveSession
from workcell.server.session_relay import SessionArgs, pacing_values
from workcell.task.pacing import PacingStats


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
        pacing = live.pacing if live is not None else PacingStats()
        self.send(("state", text, pacing_values(pacing)))

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


def run_child(conn: Connection, args: SessionArgs) -> threading.Thread | None:
    """Run the session until it ends (its end went down the pipe); the thread still
    obeying the server (None when the session did not start), which returns once the
    server closes its end."""
    if threading.current_thread() is threading.main_thread():
        signal.signal(signal.SIGINT, signal.SIG_IGN)  # the server decides when a session stops
    listener = _PipeListener(conn)
    root = logging.getLogger()
    root.handlers[:] = [_PipeLogHandler(listener)]
    root.setLevel(logging.INFO)
    obedience = _Obedience(conn)
    try:  # a driver that cannot be built (a policy not found) refuses the start too
        live = LiveSession(
            args.config, args.store_path, listener, args.state_hz, args.max_catch_up_s,
            key_file=args.key_file, idle=obedience.idle,
        )  # fmt: skip
        listener.live = obedience.live = live
        live.start()
    except BaseException as error:  # told to the server, which refuses the start
        message = str(error) if isinstance(error, WorkcellError) else f"the server failed: {error}"
        listener.first(("failed", message))
        return None
    listener.first(("ready", live.session_id, live.scene))
    live.join()
    commands = threading.Thread(target=obedience.until_closed, daemon=True)
    commands.start()
    return commands


class _Obedience:
    """Applies the server's requests to the session. The server closes the pipe only after
    the session has ended (an orderly shutdown first asks for ``application_quit``), so a
    pipe closed while the session runs means the server died: the trial ends as
    ``crash_recovered``, as if a crash recovery had closed it."""

    def __init__(self, conn: Connection) -> None:
        self.conn = conn
        self.live: LiveSession | None = None
        self.closed = False
        self._readable = select.poll()
        """The pipe, polled in one call (``Connection.poll`` builds a selector each time)."""
        self._readable.register(conn.fileno(), select.POLLIN)

    def idle(self, seconds: float) -> None:
        """The simulation thread's wait (:data:`~workcell.task.pacing.Idle`): up to
        ``seconds`` for the server to say something, then everything it has said."""
        if self.closed:
            time.sleep(seconds)  # the stop is requested: the loop ends at its next look
            return
        try:
            if not self._readable.poll(1000.0 * seconds):
                return
            while True:
                self._apply(self.conn.recv())
                if not self._readable.poll(0):
                    break
        except (EOFError, OSError):
            self._server_gone()
        if self.live is not None:
            self.live.apply_requests()  # before a stop among them ends the trial

    def until_closed(self) -> None:
        """Read (and apply, to an ended session: nothing) until the server closes its end."""
        while not self.closed:
            try:
                self._apply(self.conn.recv())
            except (EOFError, OSError):
                self._server_gone()

    def _server_gone(self) -> None:
        self.closed = True
        if self.live is not None:
            self.live.request_stop("crash_recovered")

    def _apply(self, message: tuple[Any, ...]) -> None:
        live = self.live
        assert live is not None
        kind, *body = message
        if kind == "input":
            live.operator.submit(body[0])
        elif kind == "new_link":
            live.operator.new_link()
        elif kind == "act":
            live.request_action(body[0], body[1])
        elif kind == "frames":
            live.report_frames(body[0])
        elif kind == "drive":
            live.request_driving(body[0], body[1])
        elif kind == "pause":
            live.request_pause(body[0])
        elif kind == "stop":
            live.request_stop(*body)

"""A live session in a process of its own: what lets one server run many sessions on all
its cores, and keeps a session whose simulation dies (a crash in native code, a kill) from
taking the server or any other session with it.

:class:`SessionProcess` is a :class:`~workcell.server.session_relay.RelayedSession` whose
child (:func:`~workcell.server.session_child.run_child`) is a process on this machine,
talking to the server over one pipe (its log records too: they are logged in the server as
its own). Processes start from a fork server that has imported the simulation once, so a
session starts in well under a second. When the child dies, the session ends ``error`` for
its clients, naming the exit; its trial stays open in its store and is closed
``interrupted`` (``crash_recovered``) when the store is next opened for writing (the
shard's merge, for a server with several seats).
"""

from __future__ import annotations

import multiprocessing
import signal
from multiprocessing.connection import Connection
from multiprocessing.context import ForkServerContext

from workcell.server.session_child import run_child
from workcell.server.session_listener import SessionListener
from workcell.server.session_relay import RelayedSession, SessionArgs

_context: ForkServerContext | None = None


def _processes() -> ForkServerContext:
    """The fork-server context, its server preloaded with the simulation's modules."""
    global _context  # noqa: PLW0603 - one fork server per server process, made on first use
    if _context is None:
        context = multiprocessing.get_context("forkserver")
        context.set_forkserver_preload([__name__])
        _context = context
    return _context


class SessionProcess(RelayedSession):
    """Start with :meth:`start`, which returns once the session is recording (or raises)."""

    kind = "process"

    def __init__(self, args: SessionArgs, listener: SessionListener) -> None:
        super().__init__(args, listener)
        context = _processes()
        self._server_conn, self._child_conn = context.Pipe()
        self._process = context.Process(
            target=run_child,
            args=(self._child_conn, self.args),
            name="workcell-session",
            daemon=True,
        )

    @property
    def pid(self) -> int | None:
        return self._process.pid

    def _launch(self) -> Connection:
        self._process.start()
        self._child_conn.close()  # the child's end is the child's alone
        return self._server_conn

    def _reap(self, timeout: float | None) -> None:
        self._process.join(timeout)

    @property
    def running(self) -> bool:
        return self._process.is_alive()

    def kill(self) -> None:
        self._process.kill()

    def _exit(self) -> str:
        code = self._process.exitcode
        if code is None:
            return "still running"
        if code < 0:
            return f"killed by {signal.Signals(-code).name}"
        return f"exit code {code}"

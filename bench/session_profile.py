"""cProfile of a live session's process and of the server, for ``bench/profile_crowd.py``
(issue 38). Nothing here runs unless that bench installs it.

The server is started with :data:`LAUNCH`, which calls :func:`install_server` before
``workcell serve`` runs: the server's event loop (its main thread, which also serves every
session's pipe) is profiled, and every session process it starts runs :func:`profiled_child`
instead of ``run_child``: the child profiles its simulation thread (the control loop,
the State it builds and sends, the recorder's hand-over, and the server's requests it
reads while it waits for the next period). Every profile measures the CPU time of its own thread
(``time.thread_time``), so a paced loop's sleeping is not counted, and is written as
``<kind>-<pid>-<thread>.prof`` into the folder named by ``WORKCELL_BENCH_PROFILE_DIR``
when its thread ends (the server's threads on shutdown).
"""

from __future__ import annotations

import cProfile
import functools
import os
import threading
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

PROFILE_DIR = "WORKCELL_BENCH_PROFILE_DIR"
LAUNCH = """
import argparse, sys
from bench import session_profile
from workcell.cli import serve
session_profile.install_server()
parser = argparse.ArgumentParser()
serve.register(parser.add_subparsers())
args = parser.parse_args(["serve", *sys.argv[1:]])
code = session_profile.profiled("server", "loop", args.func)(args)
sys.exit(code)
"""


def profiled(kind: str, thread: str, call: Callable[..., Any]) -> Callable[..., Any]:
    """``call`` run under cProfile (CPU time of the calling thread), its profile written
    when it returns or raises."""

    @functools.wraps(call)
    def run(*args: Any, **kwargs: Any) -> Any:
        profile = cProfile.Profile(time.thread_time)
        profile.enable()
        try:
            return call(*args, **kwargs)
        finally:
            profile.disable()
            folder = Path(os.environ[PROFILE_DIR])
            name = f"{kind}-{os.getpid()}-{thread}-{threading.get_ident()}.prof"
            profile.dump_stats(folder / name)

    return run


def install_server() -> None:
    """Have every session process profiled."""
    from workcell.server import session_process  # noqa: PLC0415

    setattr(session_process, "run_child", profiled_child)  # noqa: B010 - what the process runs


def profiled_child(conn: Any, args: Any) -> Any:
    """``run_child`` with the session's threads profiled (in the session's process)."""
    from workcell.server import live, session_child  # noqa: PLC0415

    session = live.LiveSession
    session._main = profiled("session", "sim", session._main)  # type: ignore[method-assign]
    commands = session_child.run_child(conn, args)
    if commands is not None:  # the server closes the pipe once the session has ended
        commands.join(10.0)
    return commands

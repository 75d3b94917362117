"""Standard output whose reader has gone (``workcell ... | head -n 1``).

That is not an error of the command: Python ignores SIGPIPE, so a write to the closed pipe
raises BrokenPipeError instead of ending the process as a shell expects. The command line
answers it as the shell does a process SIGPIPE ended, with status 141 and nothing on
standard error; ``workcell collect`` notices it earlier and ends its run as on SIGINT.
"""

from __future__ import annotations

import contextlib
import os
import select
import signal
import stat
import sys
from typing import IO

EXIT_OUTPUT_CLOSED = 128 + signal.SIGPIPE
"""Standard output's reader went away: the shell's status for a process SIGPIPE ended."""


def reader_gone(stream: IO[str]) -> bool:
    """True when ``stream`` is a pipe or socket whose reading end has been closed."""
    try:
        fd = stream.fileno()
        if not stat.S_ISFIFO(os.fstat(fd).st_mode) and not stat.S_ISSOCK(os.fstat(fd).st_mode):
            return False
        poller = select.poll()
        poller.register(fd, select.POLLOUT)
        return any(events & (select.POLLERR | select.POLLHUP) for _, events in poller.poll(0))
    except (OSError, ValueError):
        return False


def discard_stdout() -> None:
    """Point standard output at /dev/null, so that what is still buffered and the flush at
    exit do not fail again (the remedy the Python documentation gives for SIGPIPE)."""
    with contextlib.suppress(OSError, ValueError):
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        os.close(devnull)

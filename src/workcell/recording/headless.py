"""A recorded session run headless as a command: ``workcell collect`` and its scale-out
workers.

The session runs as fast as it goes; SIGINT or SIGTERM (or the caller's own reason to
quit, e.g. standard output closed) end its running trial as
``interrupted``/``application_quit`` and the session as ``interrupted``. The exit status
then says how it ended: :data:`EXIT_STORAGE` when recording failed (the error on standard
error; the store holds what came before), the shells' 130 or 143 after a signal.
"""

from __future__ import annotations

import sys
from collections.abc import Callable
from typing import Literal

from workcell.recording.recorded_session import RecordedSession
from workcell.recording.shutdown import ShutdownSignals, exit_status
from workcell.task.runner import TrialResult

EXIT_STORAGE = 1
"""The recording failed (disk full, I/O error, the writer process died)."""


def run_headless(
    session: RecordedSession,
    on_trial: Callable[[TrialResult], None],
    after_step: Callable[[], None] | None = None,
    should_quit: Callable[[], bool] | None = None,
) -> str | None:
    """Run ``session`` to its end, ``on_trial`` for each trial as it ends; returns the name
    of the signal that stopped it (``"SIGINT"``, ``"SIGTERM"``), or None."""
    with ShutdownSignals() as shutdown:

        def quit_reason() -> Literal["application_quit"] | None:
            quitting = shutdown.requested is not None or (should_quit is not None and should_quit())
            return "application_quit" if quitting else None

        session.run(quit_reason, after_step, on_trial)
    return shutdown.requested


def headless_status(session: RecordedSession, signal_name: str | None, otherwise: int = 0) -> int:
    """The exit status of a session :func:`run_headless` ran: :data:`EXIT_STORAGE` when its
    recording failed (said on standard error), 130 or 143 after ``signal_name``, else
    ``otherwise``."""
    if session.failure is not None:
        print(f"workcell: error: {session.failure}", file=sys.stderr)
        return EXIT_STORAGE
    return otherwise if signal_name is None else exit_status(signal_name)

"""Running an evaluation's shares in this process, one recorded session after another.

Each share is a :class:`~workcell.recording.recorded_session.RecordedSession` run headless
as ``workcell collect`` runs one (its store written by a writer process): SIGINT or SIGTERM
end the running rollout ``interrupted`` and no further share starts; a recording failure
ends the evaluation with what the store holds.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

from workcell.evaluate.plan import Share
from workcell.recording.drivers import Driver
from workcell.session.config import SessionConfig
from workcell.task.runner import TrialResult

OnTrial = Callable[[Share, TrialResult], None]
"""Called as each rollout ends, with the share it belongs to."""


@dataclass
class Ran:
    """What an evaluation run recorded, and how it ended."""

    session_ids: list[str] = field(default_factory=list)
    signal_name: str | None = None
    """The signal that stopped it (``SIGINT``, ``SIGTERM``), or None."""
    failure: str | None = None
    """Why recording failed, or None."""
    worker_deaths: list[str] = field(default_factory=list)
    """Workers that died (their shards recovered like any crashed store)."""


def run_shares(
    shares: Sequence[tuple[Share, SessionConfig]],
    driver: Driver,
    store: Path,
    on_trial: OnTrial,
) -> Ran:
    """Run every share in order, recording into ``store``."""
    from workcell.recording.headless import run_headless  # noqa: PLC0415
    from workcell.recording.recorded_session import (  # noqa: PLC0415
        RecordedSession,
        RecordedSessionConfig,
    )

    ran = Ran()
    for share, config in shares:
        recorded = RecordedSessionConfig(
            session=config, driver=driver, store=store, max_trials=share.rollouts
        )
        with RecordedSession.open(recorded) as session:

            def report(result: TrialResult, share: Share = share) -> None:
                on_trial(share, result)

            ran.signal_name = run_headless(session, report)
            if session.recorder is not None:
                ran.session_ids.append(session.session_id)
        if session.failure is not None:
            ran.failure = str(session.failure)
        if ran.signal_name is not None or ran.failure is not None:
            break
    return ran

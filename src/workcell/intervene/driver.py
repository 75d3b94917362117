"""The driver a live session's ``driver`` setting names, as its recorded session builds it."""

from __future__ import annotations

from workcell.recording.drivers import ExpertDriver, InterveningDriver, PolicyDriver, TeleopDriver
from workcell.session.config import SessionConfig

POLICY_PREFIX = "policy:"


def live_driver(config: SessionConfig) -> TeleopDriver | InterveningDriver:
    """``person``: the person at the browser drives; ``expert`` or ``policy:PATH``: that
    driver drives and the person may take over (a policy's checkpoint is found now, so a
    missing one refuses the session's start with a LearnError saying what is wrong)."""
    if config.driver == "person":
        return TeleopDriver()
    if config.driver == "expert":
        return InterveningDriver(ExpertDriver())
    from workcell.learn.checkpoint import PolicyCheckpoint  # noqa: PLC0415

    checkpoint = PolicyCheckpoint.locate(config.driver.removeprefix(POLICY_PREFIX))
    return InterveningDriver(PolicyDriver(checkpoint))

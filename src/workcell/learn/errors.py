"""Errors of the learning path."""

from __future__ import annotations

from workcell.errors import WorkcellError

INSTALL_HINT = "install the learn extra: pip install 'workcell[learn]' (or make setup-learn)"


class LearnError(WorkcellError):
    """A policy cannot be trained or run: the message says what is missing and how to fix it."""


class MissingLearnExtraError(LearnError):
    """LeRobot or torch is not installed."""

    def __init__(self, missing: str) -> None:
        super().__init__(f"{missing} is not installed; {INSTALL_HINT}")

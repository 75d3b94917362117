"""The single error root of Workcell.

Every error a user can cause derives from :class:`WorkcellError` and carries a message that
names what was wrong and what is allowed, so the command line can print it as one line.
"""

from __future__ import annotations

from collections.abc import Sequence


class WorkcellError(Exception):
    """Root of every error Workcell raises on purpose."""


class ConfigError(WorkcellError):
    """One or more configuration values are invalid.

    ``problems`` holds one line per invalid field: the field, the value and what is allowed.
    """

    def __init__(self, problems: Sequence[str]) -> None:
        self.problems: tuple[str, ...] = tuple(problems)
        super().__init__("\n".join(self.problems))


class SimulationError(WorkcellError):
    """The simulation reached a state it cannot continue from (for example NaN physics)."""


class RenderError(WorkcellError):
    """Offscreen rendering is unavailable or failed; the message says how to enable it."""


class MetricsError(WorkcellError):
    """Frames or counts given to the metrics are unusable (missing or ragged columns,
    impossible success counts); the message names every offending column or value."""

"""When the scripted corrector (:mod:`workcell.intervene.corrector`) takes over: values
only, so that a command line checks them without loading the simulation."""

from __future__ import annotations

import math
from dataclasses import dataclass

from workcell.errors import ConfigError

CORRECTORS = ("expert",)
"""Who may stand in for the person (``workcell collect --corrector``)."""
SECONDS = (0.1, 3600.0)
"""The least and the most a rule's time may be (s)."""
DROP_STAGES = ("grasped", "lifted")
"""The stages at which a box no longer held has been dropped on its way."""


@dataclass(frozen=True)
class CorrectorRules:
    """When the scripted corrector takes over."""

    stall_s: float = 8.0
    """Take over when the stage has not advanced for this long (s) while the driver drives."""
    drop_s: float = 0.5
    """Take over when no box has been held for this long (s) at a :data:`DROP_STAGES`."""
    operator_id: str = "expert"
    """Who the take-over and hand-back events name as the person."""

    def __post_init__(self) -> None:
        problems = [
            f"{name} = {value:g}: must be a finite number of seconds between "
            f"{SECONDS[0]:g} and {SECONDS[1]:g}"
            for name, value in (("stall_s", self.stall_s), ("drop_s", self.drop_s))
            if not within_seconds(value)
        ]
        if problems:
            raise ConfigError(problems)


def within_seconds(value: float) -> bool:
    """Whether ``value`` is a time a rule may have (:data:`SECONDS`)."""
    return math.isfinite(value) and SECONDS[0] <= value <= SECONDS[1]

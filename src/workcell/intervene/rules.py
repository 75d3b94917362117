"""When the scripted corrector (:mod:`workcell.intervene.corrector`) takes over: values
only, so that a command line checks them without loading the simulation."""

from __future__ import annotations

import math
from dataclasses import dataclass

from workcell.errors import ConfigError

CORRECTORS = ("expert",)
"""Who may stand in for the person (``workcell collect --corrector``)."""
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
            f"{name} = {value:g}: must be a finite number of seconds between 0.1 and 3600"
            for name, value in (("stall_s", self.stall_s), ("drop_s", self.drop_s))
            if not (math.isfinite(value) and 0.1 <= value <= 3600.0)
        ]
        if problems:
            raise ConfigError(problems)

"""Domain randomization's settings: how far each trial's box, belt, feed timing, target and
start may stray (the draw itself: :mod:`workcell.sim.trial_conditions`).

Off by default (every range 0): the paper's condition is one identical task configuration.
Turned on, each trial's conditions are drawn from its seed, applied without recompiling,
and recorded with the trial, so a dataset covers more than one configuration.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

from workcell.errors import ConfigError
from workcell.settings import declared_problems, setting


@dataclass(frozen=True)
class RandomizationConfig:
    """How far each trial's conditions may stray from the configured ones (0 = fixed)."""

    box_size: float = setting(
        0.0, "each box side scaled by up to +/- this fraction", unit="1", low=0.0, high=0.2
    )
    box_mass: float = setting(
        0.0, "box mass scaled by up to +/- this fraction", unit="1", low=0.0, high=0.5
    )
    box_colour: float = setting(
        0.0, "each colour channel moved by up to +/- this", unit="1", low=0.0, high=0.3
    )
    conveyor_speed: float = setting(
        0.0, "belt speed scaled by up to +/- this fraction", unit="1", low=0.0, high=0.5
    )
    release_interval: float = setting(
        0.0, "release interval scaled by up to +/- this fraction", unit="1", low=0.0, high=0.5
    )
    target_shift: float = setting(
        0.0, "delivery zone moved by up to this in x and y", unit="m", low=0.0, high=0.5
    )
    start_shift: float = setting(
        0.0, "robot start moved by up to this in x and y", unit="m", low=0.0, high=0.5
    )
    start_yaw: float = setting(
        0.0, "robot start turned by up to +/- this", unit="rad", low=0.0, high=0.5
    )

    def __post_init__(self) -> None:
        problems = declared_problems(self, "randomization")
        if problems:
            raise ConfigError(problems)

    @property
    def enabled(self) -> bool:
        return any(getattr(self, f.name) > 0 for f in dataclasses.fields(self))

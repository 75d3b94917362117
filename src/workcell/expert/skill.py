"""How good the expert is: a seeded draw of speeds, pauses, detours and hand noise.

``skill`` 1 is the best expert (direct, brisk, steady). Lower skill hesitates between
phases, takes detours while carrying, moves slower and adds tremor to the hands, so it also
produces slow runs and timeouts like a human operator.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from workcell import checks
from workcell.errors import ConfigError

MAX_BASE_NOISE = 0.5
"""m/s: the largest ``base_noise`` (two thirds of the robot's top speed)."""


@dataclass(frozen=True)
class ExpertConfig:
    skill: float = 1.0
    base_noise: float = 0.0
    """m/s: the standard deviation of a perturbation added to the base's twist while the
    expert drives, so that its demonstrations show it steering back (0: none;
    :mod:`workcell.expert.noise`)."""

    def __post_init__(self) -> None:
        problems = checks.in_range("skill", self.skill, 0.0, 1.0)
        problems += checks.in_range("base_noise", self.base_noise, 0.0, MAX_BASE_NOISE)
        if problems:
            raise ConfigError(problems)


@dataclass(frozen=True)
class SkillProfile:
    """Concrete behaviour parameters drawn once per trial."""

    speed_scale: float
    reaction_s: float
    """How long the expert takes to react once a box has come to rest."""
    hesitation_probability: float
    max_hesitation_s: float
    detour_m: float
    tremor_m: float
    lateral_offset_m: float
    pick_distance_m: float
    place_offset: tuple[float, float]

    @staticmethod
    def draw(skill: float, rng: np.random.Generator) -> SkillProfile:
        clumsy = 1.0 - skill
        return SkillProfile(
            speed_scale=float(rng.uniform(0.85, 1.0) * (1.0 - 0.55 * clumsy)),
            reaction_s=float(rng.uniform(0.2, 1.5) * (1.0 + 3.0 * clumsy)),
            hesitation_probability=0.7 * clumsy,
            max_hesitation_s=25.0 * clumsy,
            detour_m=float(rng.uniform(0.0, 1.5) * clumsy),
            tremor_m=0.012 * clumsy,
            lateral_offset_m=float(rng.uniform(-0.03, 0.03)),
            pick_distance_m=float(rng.uniform(0.58, 0.62)),
            place_offset=(float(rng.uniform(-0.06, 0.06)), float(rng.uniform(-0.08, 0.08))),
        )

"""How long a join takes: as long as its longest move at the join speeds, where an arm
the target does not have following (a person's released clutch, whose recorded target is
often none) covers no distance."""

from __future__ import annotations

import numpy as np
import pytest

from workcell.generate.join import JOIN_SPEED, MIN_JOIN_S, join_duration
from workcell.generate.motion import MotionSample, smoothstep, smoothstep_rate
from workcell.generate.planar import Planar


def hands_at(*points: tuple[float, float, float]) -> np.ndarray:
    hands = np.zeros((2, 7))
    hands[:, 3] = 1.0
    hands[:, :3] = points
    return hands


def target(hands: np.ndarray, follow: tuple[bool, bool]) -> MotionSample:
    return MotionSample(np.zeros(3), np.zeros(3), hands, follow, (0.0, 0.0), (0.0, 0.0))


def test_a_following_arm_far_away_makes_the_join_long() -> None:
    here = hands_at((0.5, 0.2, 1.0), (0.5, -0.2, 1.0))
    there = hands_at((0.5, 0.2, 1.0), (0.5, -0.2, 0.0))
    duration = join_duration(np.zeros(3), here, target(there, (True, True)))
    assert duration == pytest.approx(1.5 * 1.0 / JOIN_SPEED[2])


def test_an_arm_not_following_adds_nothing_however_far_its_recorded_target() -> None:
    here = hands_at((0.5, 0.2, 1.0), (0.5, -0.2, 1.0))
    there = hands_at((0.5, 0.2, 1.0), (0.0, 0.0, -0.02))
    assert join_duration(np.zeros(3), here, target(there, (True, False))) == MIN_JOIN_S
    there[1] = np.nan
    assert join_duration(np.zeros(3), here, target(there, (True, True))) == MIN_JOIN_S


def test_a_motion_eases_into_none() -> None:
    motion = Planar(0.4, -0.2, 0.3)
    assert motion.scaled(1.0) == motion
    assert motion.scaled(0.0) == Planar()
    assert motion.scaled(0.5) == Planar(0.2, -0.1, 0.15)


def test_the_ease_starts_and_ends_at_rest() -> None:
    assert (smoothstep(0.0), smoothstep(0.5), smoothstep(1.0)) == (0.0, 0.5, 1.0)
    step = 1e-6
    assert smoothstep(step) / step < 1e-5
    assert (1.0 - smoothstep(1.0 - step)) / step < 1e-5
    assert smoothstep_rate(0.5) == pytest.approx(
        (smoothstep(0.5 + step) - smoothstep(0.5 - step)) / (2 * step)
    )

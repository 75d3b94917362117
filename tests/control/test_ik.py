"""Differential IK: reachable side-grasp targets converge, joint limits always hold."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from numpy.typing import NDArray

from workcell.control.ik import BimanualIK
from workcell.sim.config import WorldConfig

Quat = tuple[float, float, float, float]

DT = 0.02
STEPS = 200
TOLERANCE = 0.005
LIMIT_SLACK = 1e-9

GRID = list(itertools.product((0.5, 0.6, 0.7), (0.75, 0.9, 1.1)))


@pytest.fixture(scope="module")
def ik() -> BimanualIK:
    return BimanualIK(WorldConfig(), home_spine=0.1)


def limit_violation(ik: BimanualIK) -> float:
    """Largest excursion (m or rad) of any limited joint outside its range; <= 0 if none."""
    model, q = ik.model, ik.configuration.q
    limited = np.flatnonzero(model.jnt_limited)
    adr = model.jnt_qposadr[limited]
    low, high = model.jnt_range[limited].T
    values: NDArray[np.float64] = np.maximum(low - q[adr], q[adr] - high)
    return float(values.max())


def drive(
    ik: BimanualIK, left: tuple[float, ...], right: tuple[float, ...], q: dict[str, Quat]
) -> float:
    """Run the IK toward both targets from home; returns the worst limit violation seen."""
    ik.reset(ik.home)
    ik.set_target("l", left, q["l"])
    ik.set_target("r", right, q["r"])
    worst = limit_violation(ik)
    for _ in range(STEPS):
        joints = ik.step(DT)
        assert np.isfinite(joints).all()
        worst = max(worst, limit_violation(ik))
    return worst


@pytest.mark.parametrize(("x", "z"), GRID, ids=[f"x{x}-z{z}" for x, z in GRID])
def test_reachable_targets_converge_within_limits(
    ik: BimanualIK, tcp_quats: dict[str, Quat], x: float, z: float
) -> None:
    worst = drive(ik, (x, 0.15, z), (x, -0.15, z), tcp_quats)
    assert worst <= LIMIT_SLACK, f"a joint left its range by {worst:.2e}"
    residuals = {side: ik.residual(side) for side in ("l", "r")}
    assert max(residuals.values()) < TOLERANCE, residuals


def test_converged_orientation_matches_target(ik: BimanualIK, tcp_quats: dict[str, Quat]) -> None:
    drive(ik, (0.6, 0.15, 0.9), (0.6, -0.15, 0.9), tcp_quats)
    for side in ("l", "r"):
        target = ik.frame_tasks[side].transform_target_to_world
        assert target is not None
        error = (ik.tcp_pose(side).rotation().inverse() @ target.rotation()).log()
        assert np.linalg.norm(error) < 0.02, (side, error)


def test_unreachable_target_is_safe(ik: BimanualIK, tcp_quats: dict[str, Quat]) -> None:
    worst = drive(ik, (2.0, 0.4, 0.9), (2.0, -0.4, 0.9), tcp_quats)
    assert worst <= LIMIT_SLACK, f"a joint left its range by {worst:.2e}"
    for side in ("l", "r"):
        assert ik.residual(side) > 0.5  # it cannot get there, and says so


def test_targets_are_independent_per_side(ik: BimanualIK, tcp_quats: dict[str, Quat]) -> None:
    """Moving only the left target leaves the right TCP where it was held."""
    ik.reset(ik.home)
    right_before = ik.tcp_pose("r").translation()
    ik.set_target("l", (0.6, 0.15, 0.9), tcp_quats["l"])
    for _ in range(STEPS):
        ik.step(DT)
    assert ik.residual("l") < TOLERANCE
    np.testing.assert_allclose(ik.tcp_pose("r").translation(), right_before, atol=0.005)


def test_target_positions_are_the_frame_tasks_targets(
    ik: BimanualIK, tcp_quats: dict[str, Quat]
) -> None:
    """The targets the recorder captures (and the residuals made from them) are those the
    frame tasks hold, after a reset, a new target, a step and a hold."""

    def check() -> None:
        for i, side in enumerate(("l", "r")):
            target = ik.frame_tasks[side].transform_target_to_world
            assert target is not None
            np.testing.assert_array_equal(ik.target_positions[i], target.translation())
            error = ik.tcp_pose(side).translation() - target.translation()
            assert ik.residual(side) == pytest.approx(np.linalg.norm(error), abs=1e-12)

    ik.reset(ik.home)
    check()
    ik.set_target("l", (0.6, 0.15, 0.9), tcp_quats["l"])
    check()
    assert ik.residual("l") > 0.01  # the target moved, the TCP not yet
    ik.step(DT)
    check()
    ik.hold("l")
    check()
    assert ik.residual("l") < 1e-12


def test_a_target_asked_again_after_a_hold_is_set_again(
    ik: BimanualIK, tcp_quats: dict[str, Quat]
) -> None:
    """The same target asked twice is set once; after a hold (the target becomes where the
    hand is) or a reset, asking for it again sets it again."""
    ik.reset(ik.home)
    wanted = (0.6, 0.15, 0.9)

    def target() -> NDArray[np.float64]:
        transform = ik.frame_tasks["l"].transform_target_to_world
        assert transform is not None
        return np.asarray(transform.translation())

    ik.set_target("l", wanted, tcp_quats["l"])
    first = ik.frame_tasks["l"].transform_target_to_world
    ik.set_target("l", wanted, tcp_quats["l"])
    assert ik.frame_tasks["l"].transform_target_to_world is first  # unchanged, not rebuilt
    ik.step(DT)
    ik.hold("l")
    assert np.linalg.norm(target() - wanted) > 0.01  # held where the hand got to
    ik.set_target("l", wanted, tcp_quats["l"])
    np.testing.assert_array_equal(target(), wanted)
    ik.reset(ik.home)
    assert np.linalg.norm(target() - wanted) > 0.01
    ik.set_target("l", wanted, tcp_quats["l"])
    np.testing.assert_array_equal(target(), wanted)
    np.testing.assert_array_equal(ik.target_positions[0], wanted)

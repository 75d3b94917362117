"""The IK keeps the two arms apart: asked to cross, they stop short of each other."""

from __future__ import annotations

import mujoco
import numpy as np

from workcell.control.ik import BimanualIK, arm_geoms
from workcell.sim.config import WorldConfig

DT = 0.025


def _closest(ik: BimanualIK) -> float:
    """The smallest distance between any left-arm geom and any right-arm geom (m)."""
    model, data = ik.model, ik.configuration.data
    fromto = np.zeros(6)
    left = [model.geom(name).id for name in arm_geoms("l")]
    right = [model.geom(name).id for name in arm_geoms("r")]
    return min(
        float(mujoco.mj_geomDistance(model, data, a, b, 1.0, fromto)) for a in left for b in right
    )


def test_arms_asked_to_cross_stop_short_of_each_other() -> None:
    ik = BimanualIK(WorldConfig(), home_spine=0.1)
    start = _closest(ik)
    left = ik.tcp_pose("l")
    right = ik.tcp_pose("r")
    # Each hand is asked to where the other one is, 5 cm lower and higher: the arms would
    # have to pass through each other.
    ik.set_target(
        "l", right.translation() + np.array([0.0, 0.0, -0.05]), tuple(left.rotation().wxyz)
    )
    ik.set_target(
        "r", left.translation() + np.array([0.0, 0.0, 0.05]), tuple(right.rotation().wxyz)
    )
    closest = start
    for _ in range(200):
        ik.step(DT)
        closest = min(closest, _closest(ik))
    travelled = np.linalg.norm(ik.tcp_pose("l").translation() - left.translation())
    assert travelled > 0.1, "the arms moved towards each other"
    assert start > 0.1
    assert closest > 0.005, f"the arms came within {closest * 1000:.1f} mm of each other"

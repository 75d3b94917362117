"""The IK's collision limits are inactive while no pair is near, and only then: over random
arm configurations and conveyor proxy positions, whenever the gate says no pair is near,
mink's own limit bounds nothing (every row's bound is infinite), and otherwise the limit
gives mink's rows; a hand at the conveyor makes its limit active."""

from __future__ import annotations

import math

import mink
import numpy as np

from workcell.control.collision_limit import StepCollisionLimit
from workcell.control.ik import BimanualIK, arm_geoms
from workcell.sim.config import WorldConfig

DT = 0.025


def _own_limits(ik: BimanualIK) -> list[mink.CollisionAvoidanceLimit]:
    """mink's limits over the pairs and distances the IK uses, ungated."""
    arms = [*arm_geoms("l"), *arm_geoms("r")]
    pairs = ([(arms, ["obstacle_proxy_geom"])], [(arm_geoms("l"), arm_geoms("r"))])
    return [
        mink.CollisionAvoidanceLimit(
            ik.model,
            geom_pairs=geom_pairs,
            minimum_distance_from_collisions=limit.minimum_distance_from_collisions,
            collision_detection_distance=limit.collision_detection_distance,
        )
        for geom_pairs, limit in zip(pairs, ik.limits[2:], strict=True)
        if isinstance(limit, StepCollisionLimit)
    ]


def test_the_gate_leaves_out_only_limits_that_bound_nothing() -> None:
    ik = BimanualIK(WorldConfig(), home_spine=0.1)
    limits = [limit for limit in ik.limits if isinstance(limit, StepCollisionLimit)]
    assert len(limits) == 2  # arms against the conveyor proxy, and arm against arm
    plains = _own_limits(ik)
    assert len(plains) == 2
    for limit, plain in zip(limits, plains, strict=True):
        assert sorted(plain.geom_id_pairs) == sorted(limit.geom_id_pairs)
    model = ik.model
    rng = np.random.default_rng(7)
    low, high = model.jnt_range[:, 0], model.jnt_range[:, 1]
    gated = {id(limit): 0 for limit in limits}
    near = {id(limit): 0 for limit in limits}
    for _ in range(300):
        q = ik.configuration.q.copy()
        for joint in range(model.njnt):
            if model.jnt_limited[joint]:
                q[model.jnt_qposadr[joint]] = rng.uniform(low[joint], high[joint])
        proxy = rng.uniform((0.1, -0.8, 0.0), (1.0, 0.8, 1.0))  # base frame, around the arms
        ik.place_obstacle(proxy, (1.0, 0.0, 0.0, 0.0))
        ik.configuration.update(q)
        for limit, plain in zip(limits, plains, strict=True):
            constraint = limit.compute_qp_inequalities(ik.configuration, DT)
            own = plain.compute_qp_inequalities(ik.configuration, DT)
            assert own.h is not None
            if constraint.inactive:
                gated[id(limit)] += 1
                assert np.all(np.isinf(own.h)), "a pair within reach was left out"
            else:
                near[id(limit)] += 1
                assert constraint.h is not None
                finite = np.isfinite(own.h)
                np.testing.assert_allclose(constraint.h[finite], own.h[finite] * DT)
    conveyor, arms = limits
    assert gated[id(conveyor)] > 0 and near[id(conveyor)] > 0  # the test saw both sides
    assert gated[id(arms)] == 0  # not gated: the shoulders are always within reach


def test_a_hand_at_the_conveyor_makes_its_limit_active() -> None:
    ik = BimanualIK(WorldConfig(), home_spine=0.1)
    conveyor_limit = ik.limits[2]
    assert isinstance(conveyor_limit, StepCollisionLimit)
    ik.place_obstacle((3.0, 0.0, 0.5), (1.0, 0.0, 0.0, 0.0))  # far away
    ik.configuration.update()
    assert not conveyor_limit.near(ik.configuration.data)
    assert conveyor_limit.compute_qp_inequalities(ik.configuration, DT).inactive
    hand = ik.tcp_pose("l").translation()
    ik.place_obstacle(hand + np.array([0.0, 0.0, -0.3]), (1.0, 0.0, 0.0, 0.0))
    ik.configuration.update()
    assert conveyor_limit.near(ik.configuration.data)
    constraint = conveyor_limit.compute_qp_inequalities(ik.configuration, DT)
    assert constraint.h is not None and any(math.isfinite(h) for h in constraint.h)

"""The IK's joint limits built once give mink's own rows and bounds, bit for bit, and the
IK's solve without the rows that bound nothing gives qpsolvers' answer on the whole QP,
bit for bit, over random arm configurations, targets and conveyor positions."""

from __future__ import annotations

import mink
import mujoco
import numpy as np
import pytest
import qpsolvers

from workcell.control.ik import BimanualIK
from workcell.control.ik_limits import FixedRowsConfigurationLimit, FixedVelocityLimit
from workcell.errors import ConfigError
from workcell.sim.config import WorldConfig

DT = 0.025


def _random_configurations(ik: BimanualIK, count: int, seed: int) -> list[np.ndarray]:
    model = ik.model
    rng = np.random.default_rng(seed)
    low, high = model.jnt_range[:, 0], model.jnt_range[:, 1]
    configurations = []
    for _ in range(count):
        q = ik.configuration.q.copy()
        for joint in range(model.njnt):
            if model.jnt_limited[joint]:
                q[model.jnt_qposadr[joint]] = rng.uniform(low[joint], high[joint])
        configurations.append(q)
    return configurations


def test_the_fixed_limits_give_minks_rows_and_bounds() -> None:
    ik = BimanualIK(WorldConfig(), home_spine=0.1)
    configuration_limit, velocity_limit = ik.limits[:2]
    assert isinstance(configuration_limit, FixedRowsConfigurationLimit)
    assert isinstance(velocity_limit, FixedVelocityLimit)
    own_configuration = mink.ConfigurationLimit(ik.model)
    own_velocity = mink.VelocityLimit(ik.model, velocity_limit.velocities)
    for q in _random_configurations(ik, 100, seed=3):
        ik.configuration.update(q)
        for dt in (DT, 0.01):
            for fixed, own in ((configuration_limit, own_configuration),
                               (velocity_limit, own_velocity)):  # fmt: skip
                ours = fixed.compute_qp_inequalities(ik.configuration, dt)
                theirs = own.compute_qp_inequalities(ik.configuration, dt)
                assert ours.G is not None and ours.h is not None
                assert theirs.G is not None and theirs.h is not None
                assert np.array_equal(ours.G, theirs.G)
                assert np.array_equal(ours.h, theirs.h), type(fixed).__name__


def test_the_solve_without_unbounding_rows_is_qpsolvers_answer() -> None:
    ik = BimanualIK(WorldConfig(), home_spine=0.1)
    tasks = [*ik.frame_tasks.values(), ik.posture]
    rng = np.random.default_rng(5)
    left_out = 0
    for q in _random_configurations(ik, 60, seed=4):
        ik.configuration.update(q)
        ik.place_obstacle(rng.uniform((0.1, -0.8, 0.0), (1.0, 0.8, 1.0)), (1.0, 0.0, 0.0, 0.0))
        for side in ("l", "r"):
            target = [float(x) for x in rng.uniform((0.2, -0.5, 0.6), (0.8, 0.5, 1.3))]
            ik.set_target(side, target, (1.0, 0.0, 0.0, 0.0))
        ik.configuration.update(q)
        problem = mink.build_ik(ik.configuration, tasks, DT, 1e-3, ik.limits)
        assert problem.h is not None
        left_out += int(np.sum(~np.isfinite(problem.h)))
        whole = qpsolvers.solve_problem(problem, solver="daqp")
        assert whole.found and whole.x is not None
        assert np.array_equal(ik.solve(DT), whole.x / DT)
    assert left_out > 0  # rows were left out, so the comparison means something


def test_a_model_with_a_free_joint_is_refused() -> None:
    model = mujoco.MjModel.from_xml_string(
        "<mujoco><worldbody><body><freejoint/><geom size='0.1'/></body></worldbody></mujoco>"
    )
    with pytest.raises(ConfigError, match="hinge and slide joints only"):
        FixedRowsConfigurationLimit(model)
    with pytest.raises(ConfigError, match="hinge and slide joints only"):
        FixedVelocityLimit(model, {})

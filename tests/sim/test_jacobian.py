"""The TCP site Jacobians of both compiled models agree with finite differences."""

from __future__ import annotations

from collections.abc import Callable

import mujoco
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from numpy.typing import NDArray

from workcell.sim.config import WorldConfig
from workcell.sim.joints import BASE_JOINTS, SIDES, SPINE_JOINT, arm_joint_names
from workcell.sim.scene import build_ik_model, build_world_model

EPS = 1e-6
REL_TOL = 1e-4

MODELS: dict[str, Callable[[WorldConfig], mujoco.MjModel]] = {
    "world": build_world_model,
    "ik": build_ik_model,
}


@pytest.fixture(scope="module", params=list(MODELS))
def model(request: pytest.FixtureRequest) -> mujoco.MjModel:
    return MODELS[str(request.param)](WorldConfig())


def site_pose(
    model: mujoco.MjModel, data: mujoco.MjData, site: int
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    mujoco.mj_kinematics(model, data)
    return data.site_xpos[site].copy(), data.site_xmat[site].reshape(3, 3).copy()


def finite_difference_columns(
    model: mujoco.MjModel, data: mujoco.MjData, site: int, joint: int
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Central differences of the site position and orientation w.r.t. one scalar joint."""
    adr = model.jnt_qposadr[joint]
    q0 = data.qpos.copy()
    data.qpos[adr] = q0[adr] + EPS
    p_plus, r_plus = site_pose(model, data, site)
    data.qpos[adr] = q0[adr] - EPS
    p_minus, r_minus = site_pose(model, data, site)
    data.qpos[:] = q0
    mujoco.mj_kinematics(model, data)
    quat = np.zeros(4)
    mujoco.mju_mat2Quat(quat, (r_plus @ r_minus.T).ravel())
    omega = np.zeros(3)
    mujoco.mju_quat2Vel(omega, quat, 2 * EPS)  # world-frame angular velocity
    return (p_plus - p_minus) / (2 * EPS), omega


def random_configuration(model: mujoco.MjModel, fractions: list[float]) -> mujoco.MjData:
    """Every limited scalar joint at a fraction of its range; base (if any) anywhere."""
    data = mujoco.MjData(model)
    scalar = [
        j
        for j in range(model.njnt)
        if model.jnt_type[j] in (mujoco.mjtJoint.mjJNT_HINGE, mujoco.mjtJoint.mjJNT_SLIDE)
    ]
    for k, j in enumerate(scalar):
        f = fractions[k % len(fractions)]
        if model.jnt_limited[j]:
            low, high = model.jnt_range[j]
            data.qpos[model.jnt_qposadr[j]] = low + f * (high - low)
        else:
            data.qpos[model.jnt_qposadr[j]] = (f - 0.5) * 4.0
    mujoco.mj_forward(model, data)
    return data


@settings(max_examples=15, deadline=None)
@given(fractions=st.lists(st.floats(min_value=0.02, max_value=0.98), min_size=23, max_size=23))
def test_tcp_jacobian_matches_finite_differences(
    model: mujoco.MjModel, fractions: list[float]
) -> None:
    data = random_configuration(model, fractions)
    for side in SIDES:
        site = model.site(f"tcp_{side}").id
        jacp = np.zeros((3, model.nv))
        jacr = np.zeros((3, model.nv))
        mujoco.mj_jacSite(model, data, jacp, jacr, site)
        names = [SPINE_JOINT, *arm_joint_names(side)]
        names += [
            n for n in BASE_JOINTS if mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, n) >= 0
        ]
        analytic = []
        numeric = []
        for name in names:
            joint = model.joint(name).id
            dof = model.jnt_dofadr[joint]
            dp, dr = finite_difference_columns(model, data, site, joint)
            analytic.append(np.concatenate([jacp[:, dof], jacr[:, dof]]))
            numeric.append(np.concatenate([dp, dr]))
        a, n = np.array(analytic), np.array(numeric)
        scale = max(1.0, float(np.linalg.norm(a)))
        assert np.linalg.norm(a - n) <= REL_TOL * scale, (side, np.abs(a - n).max())


def test_tcp_does_not_depend_on_the_other_arm_or_the_head(model: mujoco.MjModel) -> None:
    data = random_configuration(model, [0.3, 0.7, 0.45])
    for side, other in (("l", "r"), ("r", "l")):
        jacp = np.zeros((3, model.nv))
        jacr = np.zeros((3, model.nv))
        mujoco.mj_jacSite(model, data, jacp, jacr, model.site(f"tcp_{side}").id)
        for name in (*arm_joint_names(other), "head_pan", "head_tilt"):
            dof = model.jnt_dofadr[model.joint(name).id]
            assert not jacp[:, dof].any(), name
            assert not jacr[:, dof].any(), name
        for name in arm_joint_names(side):
            dof = model.jnt_dofadr[model.joint(name).id]
            assert jacr[:, dof].any(), name  # every arm joint turns its own TCP

"""The frozen 17-joint order and its agreement with the compiled models."""

from __future__ import annotations

from collections.abc import Callable

import mujoco
import pytest

from workcell.sim.config import WorldConfig
from workcell.sim.joints import JOINT_ORDER
from workcell.sim.scene import build_ik_model, build_world_model

EXPECTED = (
    "spine",
    "head_pan",
    "head_tilt",
    *(f"arm_l_{i}" for i in range(1, 8)),
    *(f"arm_r_{i}" for i in range(1, 8)),
)


def test_joint_order_is_frozen() -> None:
    assert len(JOINT_ORDER) == 17
    assert len(set(JOINT_ORDER)) == 17
    assert JOINT_ORDER == EXPECTED


@pytest.mark.parametrize("build", [build_world_model, build_ik_model], ids=["world", "ik"])
def test_every_joint_is_in_the_compiled_model(
    build: Callable[[WorldConfig], mujoco.MjModel],
) -> None:
    model = build(WorldConfig())
    names = {model.joint(j).name for j in range(model.njnt)}
    missing = [n for n in JOINT_ORDER if n not in names]
    assert not missing
    for name in JOINT_ORDER:
        joint = model.joint(name)
        expected = mujoco.mjtJoint.mjJNT_SLIDE if name == "spine" else mujoco.mjtJoint.mjJNT_HINGE
        assert joint.type[0] == expected, name
        assert model.jnt_limited[joint.id], f"{name} must have limits"


def test_every_joint_has_a_position_actuator() -> None:
    model = build_world_model(WorldConfig())
    for name in JOINT_ORDER:
        actuator = model.actuator(name)
        assert actuator.trnid[0] == model.joint(name).id, name

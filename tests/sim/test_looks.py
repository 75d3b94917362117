"""The workcell's looks change nothing of how it moves: decor is massless and contact-free."""

from __future__ import annotations

import mujoco
import numpy as np

from workcell.sim.config import WorldConfig
from workcell.sim.looks import DECOR_PREFIX
from workcell.sim.scene import world_spec


def _without_decor() -> mujoco.MjSpec:
    spec = world_spec(WorldConfig())
    for geom in [g for g in spec.geoms if g.name.startswith(DECOR_PREFIX)]:
        spec.delete(geom)
    return spec


def _run(model: mujoco.MjModel, steps: int) -> np.ndarray:
    """The robot swinging every joint towards its range's middle, a box released on the
    belt: the whole state after ``steps``."""
    data = mujoco.MjData(model)
    mujoco.mj_resetData(model, data)
    box = model.body("box_0")
    joint = model.jnt_qposadr[model.body_jntadr[box.id]]
    data.qpos[joint : joint + 3] = (-2.6, 0.0, 1.0)
    model.body_gravcomp[box.id] = 0.0
    data.ctrl[:] = np.mean(model.actuator_ctrlrange, axis=1) * (model.actuator_ctrllimited > 0)
    for _ in range(steps):
        mujoco.mj_step(model, data)
    return np.concatenate([data.qpos, data.qvel])


def test_decor_is_massless_and_touches_nothing() -> None:
    model = world_spec(WorldConfig()).compile()
    decor = [g for g in range(model.ngeom) if model.geom(g).name.startswith(DECOR_PREFIX)]
    assert len(decor) >= 20, "floor markings, arm collars, status strip, lidar"
    assert all(model.geom_contype[g] == 0 and model.geom_conaffinity[g] == 0 for g in decor)
    bare = _without_decor().compile()
    assert bare.ngeom == model.ngeom - len(decor)
    for field in ("body_mass", "body_inertia", "body_ipos", "body_iquat", "body_subtreemass"):
        np.testing.assert_array_equal(getattr(model, field), getattr(bare, field), err_msg=field)


def test_the_world_moves_the_same_with_and_without_decor() -> None:
    dressed = _run(world_spec(WorldConfig()).compile(), 400)
    bare = _run(_without_decor().compile(), 400)
    assert np.abs(dressed).max() > 0.1, "the run moved something"
    np.testing.assert_array_equal(dressed, bare)


def test_every_visible_part_of_the_robot_and_the_workcell_has_a_material() -> None:
    """Camera renders and the browser shade by material; a geom without one is drawn flat."""
    model = world_spec(WorldConfig()).compile()
    bare = [
        model.geom(g).name or f"geom {g}"
        for g in range(model.ngeom)
        if model.geom_matid[g] < 0 and model.geom_rgba[g, 3] >= 0.999
    ]
    assert bare == []
    names = {model.material(i).name for i in range(model.nmat)}
    assert {"floor_mat", "robot_shell", "painted_steel", "rubber", "cardboard"} <= names

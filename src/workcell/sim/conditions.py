"""Putting a trial's conditions into the compiled model, without recompiling."""

from __future__ import annotations

import mujoco
import numpy as np

from workcell.sim.boxes import BoxPool, BoxSlot
from workcell.sim.trial_conditions import TrialConditions

TAPE_HALF_WIDTH = 0.03
TAPE_HALF_THICKNESS = 0.002


def apply_conditions(
    model: mujoco.MjModel, data: mujoco.MjData, pool: BoxPool, conditions: TrialConditions
) -> None:
    """Box size, mass and colour; belt speed; target position. Then the model's derived
    constants are recomputed (``mj_setConst``) so masses and sizes act consistently."""
    for slot in pool.slots:
        shape_box(model, slot, conditions.box_size, conditions.box_mass, conditions.box_rgba)
    model.geom_surfacevel[model.geom("belt").id, 0] = conditions.conveyor_speed
    model.body_pos[model.body("target").id, :2] = conditions.target_center
    mujoco.mj_setConst(model, data)


def shape_box(
    model: mujoco.MjModel,
    slot: BoxSlot,
    size: tuple[float, float, float],
    mass: float,
    rgba: tuple[float, float, float, float],
) -> None:
    """One pooled box's sides, mass (a solid box's inertia) and colour, its tape strip
    following; the caller recomputes the model's derived constants (``mj_setConst``)."""
    half = np.asarray(size, dtype=float) / 2
    a, b, c = half
    inertia = mass / 3.0 * np.array([b * b + c * c, a * a + c * c, a * a + b * b])
    geom = slot.geom
    model.geom_size[geom] = half
    model.geom_rbound[geom] = float(np.linalg.norm(half))
    model.geom_aabb[geom] = (0.0, 0.0, 0.0, a, b, c)
    model.geom_rgba[geom] = rgba
    tape = geom + 1  # the tape strip is the box body's second geom
    model.geom_size[tape] = (a + 0.001, TAPE_HALF_WIDTH, TAPE_HALF_THICKNESS)
    model.geom_pos[tape] = (0.0, 0.0, c)
    model.geom_rbound[tape] = float(np.linalg.norm(model.geom_size[tape]))
    model.body_mass[slot.body] = mass
    model.body_inertia[slot.body] = inertia

"""The IK's collision avoidance: mink's limit, with its bound in the QP's own units.

mink (1.3) writes every limit as ``G Δq <= h``, ``Δq`` the step's joint displacement (its
``VelocityLimit`` bounds ``Δq`` by ``v_max * dt``). Its ``CollisionAvoidanceLimit`` bounds
how far two geoms may approach in the step by ``gain * (d - d_min) / dt``: a velocity,
``1/dt`` times too loose as a displacement (40x at 40 Hz). Two hands 12 cm apart passed
through each other in one 25 ms step. :class:`StepCollisionLimit` scales that bound by
``dt``, so in one step a pair closes at most ``gain`` of its gap above ``d_min``: the
velocity damper the limit is meant to be.

Most of the time no pair is near: the arms work apart and above the fixtures. mink then
still runs its broadphase, builds a zero row per pair with an infinite bound and hands
them to the QP, where they constrain nothing. :class:`StepCollisionLimit` first asks, in
one vectorised test, whether any pair's bounding spheres come within the detection
distance (mink's own broadphase test, for pairs of bounded geoms); when none does, the
limit is inactive for the step and adds no rows. The IK's answer is the same: the rows
left out were ones no solution could violate. (The arm-against-arm pairs include the two
shoulders, whose spheres always overlap: that limit is not gated.)
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import mink
import mujoco
import numpy as np
from mink.limits.limit import Constraint


class StepCollisionLimit(mink.CollisionAvoidanceLimit):
    """:class:`mink.CollisionAvoidanceLimit` bounding each step's approach by
    ``gain * (d - d_min)``, inactive while no pair is near (see the module's docstring)."""

    def __init__(
        self,
        model: mujoco.MjModel,
        geom_pairs: Sequence[Any],
        *,
        gate: bool = True,
        **options: Any,
    ) -> None:
        """``gate=False`` for pairs that are nearly always within reach (the test would be
        work for nothing); ``options`` are mink's."""
        super().__init__(model, geom_pairs, **options)
        pairs = np.array(self.geom_id_pairs, dtype=int).reshape(-1, 2)
        self._first, self._second = pairs[:, 0], pairs[:, 1]
        bound = model.geom_rbound
        reach = bound[self._first] + bound[self._second] + self.collision_detection_distance
        self._reach_squared = reach * reach
        bounded = bool(np.all((bound[self._first] > 0) & (bound[self._second] > 0)))
        self._gated = gate and bounded
        """Whether to test first: asked for, and every pair is of two bounded geoms (no
        plane), so the test applies."""

    def near(self, data: mujoco.MjData) -> bool:
        """Whether any pair's bounding spheres come within the detection distance; always
        True for a limit that is not gated (``gate=False``, or a pair with an unbounded
        geom such as a plane)."""
        if not self._gated:
            return True
        apart = data.geom_xpos[self._first] - data.geom_xpos[self._second]
        return bool((np.einsum("ij,ij->i", apart, apart) <= self._reach_squared).any())

    def compute_qp_inequalities(self, configuration: mink.Configuration, dt: float) -> Constraint:
        if not self.near(configuration.data):
            return Constraint()  # inactive: no rows
        constraint = super().compute_qp_inequalities(configuration, dt)
        assert constraint.G is not None and constraint.h is not None
        return Constraint(G=constraint.G, h=constraint.h * dt)

"""The IK's collision avoidance: mink's limit, with its bound in the QP's own units.

mink (1.3) writes every limit as ``G Δq <= h``, ``Δq`` the step's joint displacement (its
``VelocityLimit`` bounds ``Δq`` by ``v_max * dt``). Its ``CollisionAvoidanceLimit`` bounds
how far two geoms may approach in the step by ``gain * (d - d_min) / dt``: a velocity,
``1/dt`` times too loose as a displacement (40x at 40 Hz). Two hands 12 cm apart passed
through each other in one 25 ms step. :class:`StepCollisionLimit` scales that bound by
``dt``, so in one step a pair closes at most ``gain`` of its gap above ``d_min``: the
velocity damper the limit is meant to be.
"""

from __future__ import annotations

import mink
from mink.limits.limit import Constraint


class StepCollisionLimit(mink.CollisionAvoidanceLimit):
    """:class:`mink.CollisionAvoidanceLimit` bounding each step's approach by
    ``gain * (d - d_min)`` (see the module's docstring)."""

    def compute_qp_inequalities(self, configuration: mink.Configuration, dt: float) -> Constraint:
        constraint = super().compute_qp_inequalities(configuration, dt)
        assert constraint.G is not None and constraint.h is not None
        return Constraint(G=constraint.G, h=constraint.h * dt)

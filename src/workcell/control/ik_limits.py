"""mink's joint limits with the work that does not change between solves done once.

mink (1.3) rebuilds every limit's rows at every solve. For the IK's robot model (hinge
and slide joints only) most of that is constant: the velocity limit's rows and bounds
depend only on the step length, and the configuration limit's rows never change, only
its bounds, which are ``gain * (upper - q)`` and ``gain * (q - lower)`` (MuJoCo's
``mj_differentiatePos`` of a hinge or slide joint is that difference, divided by the
``dt=1`` mink passes). These subclasses return the same rows and bounds, bit for bit
(``tests/control/test_ik_limits.py``), without rebuilding them.
"""

from __future__ import annotations

import mink
import mujoco
import numpy as np
from mink.limits.limit import Constraint
from numpy.typing import NDArray

from workcell.errors import ConfigError

_SCALAR_JOINTS = (mujoco.mjtJoint.mjJNT_HINGE, mujoco.mjtJoint.mjJNT_SLIDE)


def _require_scalar_joints(model: mujoco.MjModel, limit: str) -> None:
    kinds = {int(kind) for kind in model.jnt_type}
    if not kinds <= {int(kind) for kind in _SCALAR_JOINTS}:
        raise ConfigError(
            [
                f"{limit} needs a model of hinge and slide joints only (one qpos per dof); "
                "use mink's own limit for free or ball joints"
            ]
        )


class FixedRowsConfigurationLimit(mink.ConfigurationLimit):
    """:class:`mink.ConfigurationLimit` whose rows are built once; its bounds are
    computed from the configuration at each solve."""

    def __init__(self, model: mujoco.MjModel, gain: float = 0.95) -> None:
        _require_scalar_joints(model, type(self).__name__)
        super().__init__(model, gain=gain)
        projection = self.projection_matrix  # None: no joint is limited
        if projection is not None:
            self._rows = np.vstack([projection, -projection])
            self._upper = self.upper[self.indices]
            self._lower = self.lower[self.indices]

    def compute_qp_inequalities(self, configuration: mink.Configuration, dt: float) -> Constraint:
        del dt  # the bounds are positions
        if self.projection_matrix is None:
            return Constraint()
        q = configuration.q[self.indices]
        bounds: NDArray[np.float64] = np.concatenate(
            [self.gain * (self._upper - q), self.gain * (q - self._lower)]
        )
        return Constraint(G=self._rows, h=bounds)


class FixedVelocityLimit(mink.VelocityLimit):
    """:class:`mink.VelocityLimit` whose rows and bounds are built once per step length."""

    def __init__(self, model: mujoco.MjModel, velocities: dict[str, float]) -> None:
        _require_scalar_joints(model, type(self).__name__)
        super().__init__(model, velocities)
        self.velocities = dict(velocities)
        """The velocity limit of each limited joint, by name (rad/s or m/s)."""
        self._built: dict[float, Constraint] = {}

    def compute_qp_inequalities(self, configuration: mink.Configuration, dt: float) -> Constraint:
        built = self._built.get(dt)
        if built is None:
            built = super().compute_qp_inequalities(configuration, dt)
            self._built[dt] = built
        return built

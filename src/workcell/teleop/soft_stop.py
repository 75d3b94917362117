"""A soft stop for a base driven by a person: it slows before the task's fixtures, the
tables and the walls instead of driving into them.

Each control period, the chassis' distance to every fixed obstacle is measured by MuJoCo
(``mj_geomDistance``, the geoms' real shapes); the part of the commanded velocity that
heads towards an obstacle is limited to ``sqrt(2 a (d - clearance))``, the speed from which
the base can still stop at ``clearance`` braking at ``a`` (a share of its acceleration
limit). Driving away or along an obstacle is never slowed. Turning is not limited. The
base stops 2-3 cm inside its clearance at full speed (it lags the reference it tracks); the
default clearance, 5 cm, is closer than the expert ever drives (6.8 cm at the table).
"""

from __future__ import annotations

import math

import mujoco
import numpy as np

from workcell.control.command import BaseTwist
from workcell.sim.config import RobotConfig

CHASSIS = "chassis"
BRAKING_SHARE = 0.5
"""Of the base's acceleration limit, the share the soft stop plans to brake with: the
position-controlled base lags its reference, so it must not need all of it."""


class SoftStop:
    """Limits a base twist by the clearance to the fixed obstacles of ``model``."""

    def __init__(self, model: mujoco.MjModel, robot: RobotConfig) -> None:
        self.clearance = robot.human_clearance
        self._decel = BRAKING_SHARE * robot.linear_accel
        self._chassis = model.geom(CHASSIS).id
        self._obstacles = fixed_obstacles(model)
        self._reach = self.clearance + robot.max_linear_speed**2 / (2 * self._decel) + 0.05
        self._fromto = np.zeros(6)
        self.nearest = math.inf
        """The chassis' distance to the nearest obstacle at the last :meth:`limit` (m;
        inf when none is within reach, or when that twist did not move the base along the
        floor: then nothing is measured)."""

    @property
    def enabled(self) -> bool:
        return self.clearance > 0

    def limit(
        self, twist: BaseTwist, model: mujoco.MjModel, data: mujoco.MjData, yaw: float
    ) -> BaseTwist:
        """``twist`` (base frame) with its approach to every near obstacle limited."""
        self.nearest = math.inf
        if not self.enabled or (twist.vx == 0.0 and twist.vy == 0.0):
            return twist  # turning on the spot, or standing: no approach to limit
        cos, sin = math.cos(yaw), math.sin(yaw)
        velocity = np.array([cos * twist.vx - sin * twist.vy, sin * twist.vx + cos * twist.vy])
        for geom in self._obstacles:
            distance = mujoco.mj_geomDistance(
                model, data, self._chassis, geom, self._reach, self._fromto
            )
            if distance >= self._reach:
                continue
            self.nearest = min(self.nearest, distance)
            towards = self._fromto[3:5] - self._fromto[0:2]
            norm = float(np.linalg.norm(towards))
            if norm < 1e-9:  # touching: head away from the obstacle's centre
                towards = data.geom_xpos[geom][:2] - data.geom_xpos[self._chassis][:2]
                norm = float(np.linalg.norm(towards))
                if norm < 1e-9:
                    continue
            towards /= norm
            approach = float(velocity @ towards)
            allowed = math.sqrt(2 * self._decel * max(0.0, distance - self.clearance))
            if approach > allowed:
                velocity -= (approach - allowed) * towards
        vx = cos * velocity[0] + sin * velocity[1]
        vy = -sin * velocity[0] + cos * velocity[1]
        return BaseTwist(vx=float(vx), vy=float(vy), wz=twist.wz)


def fixed_obstacles(model: mujoco.MjModel) -> list[int]:
    """Geoms fixed to the world that collide (belts, tables, walls, racks), the
    floor left out."""
    out = []
    for geom in range(model.ngeom):
        fixed = model.body_weldid[model.geom_bodyid[geom]] == 0
        colliding = model.geom_contype[geom] or model.geom_conaffinity[geom]
        plane = model.geom_type[geom] == mujoco.mjtGeom.mjGEOM_PLANE
        if fixed and colliding and not plane:
            out.append(geom)
    return out

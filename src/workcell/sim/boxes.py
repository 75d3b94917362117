"""The box pool: parking, releasing onto the belt, and each box's state.

A parked box floats out of sight with gravity compensated and contacts off, so the pool
costs no contacts; releasing one only writes model and state arrays (no recompile).
"""

from __future__ import annotations

import enum
from dataclasses import dataclass

import mujoco
import numpy as np
from numpy.typing import NDArray

from workcell.sim.arena import box_name, parked_position
from workcell.sim.config import WorldConfig
from workcell.sim.spec_utils import ENV_CONAFFINITY, ENV_CONTYPE


class BoxState(enum.Enum):
    PARKED = "parked"
    ACTIVE = "active"
    DELIVERED = "delivered"


@dataclass
class BoxSlot:
    """Model indices of one pooled box and its mutable task state."""

    index: int
    body: int
    geom: int
    qpos: int
    qvel: int
    state: BoxState = BoxState.PARKED
    released_at: float = 0.0
    delivered_at: float = 0.0
    size: tuple[float, float, float] | None = None
    """This box's own sides when a task gives its boxes different ones (None: the trial's
    box size, :attr:`BoxPool.box_size`)."""


class BoxPool:
    """All boxes of the world, with release and recycling."""

    def __init__(self, model: mujoco.MjModel, config: WorldConfig) -> None:
        self._model = model
        self._config = config
        self.slots: list[BoxSlot] = []
        for i in range(config.feeder.pool_size):
            body = model.body(box_name(i)).id
            joint = model.body_jntadr[body]
            self.slots.append(
                BoxSlot(
                    index=i,
                    body=body,
                    geom=model.geom(f"{box_name(i)}_geom").id,
                    qpos=int(model.jnt_qposadr[joint]),
                    qvel=int(model.jnt_dofadr[joint]),
                )
            )
        self.pose_indices = np.array([np.arange(s.qpos, s.qpos + 7) for s in self.slots])
        """qpos indices of every box's (x, y, z, qw, qx, qy, qz), one row per box."""
        self.box_size = config.box.size
        self.feed_position: NDArray[np.float64] = np.zeros(3)
        self.set_box_size(config.box.size)

    def set_box_size(self, size: tuple[float, float, float]) -> None:
        """The size this trial's boxes have; where they land on the belt follows from it."""
        self.box_size = size
        self.feed_position = self._feed_point(size)

    def _feed_point(self, size: tuple[float, float, float]) -> NDArray[np.float64]:
        """Where a box of ``size`` lands on the belt start (its centre)."""
        c = self._config.conveyor
        return np.array(
            [c.start_x + 0.15 + size[0] / 2, c.center_y, c.height + size[2] / 2 + 0.002]
        )

    def size_of(self, slot: BoxSlot) -> tuple[float, float, float]:
        """The sides of ``slot``'s box: its own, or the trial's."""
        return self.box_size if slot.size is None else slot.size

    def park_all(self, data: mujoco.MjData) -> None:
        for slot in self.slots:
            self.park(data, slot)

    def park(self, data: mujoco.MjData, slot: BoxSlot) -> None:
        self._model.body_gravcomp[slot.body] = 1.0
        self._set_collision(slot, 0, 0)
        data.qpos[slot.qpos : slot.qpos + 3] = parked_position(slot.index)
        data.qpos[slot.qpos + 3 : slot.qpos + 7] = (1.0, 0.0, 0.0, 0.0)
        data.qvel[slot.qvel : slot.qvel + 6] = 0.0
        slot.state = BoxState.PARKED

    def _set_collision(self, slot: BoxSlot, contype: int, conaffinity: int) -> None:
        """Switch a box's contacts; the body masks are what the broadphase filters on."""
        self._model.geom_contype[slot.geom] = contype
        self._model.geom_conaffinity[slot.geom] = conaffinity
        self._model.body_contype[slot.body] = contype
        self._model.body_conaffinity[slot.body] = conaffinity

    def feed_clear(self, data: mujoco.MjData) -> bool:
        """True when no active box sits near the feed point."""
        clearance = self.box_size[0] + 0.1
        for slot in self.active():
            pos = data.qpos[slot.qpos : slot.qpos + 3]
            if np.linalg.norm(pos[:2] - self.feed_position[:2]) < clearance:
                return False
        return True

    def release(
        self, data: mujoco.MjData, t_sim: float, lateral: float = 0.0, yaw: float = 0.0
    ) -> BoxSlot | None:
        """Put the next parked box on the belt start, ``lateral`` m off the centre line and
        turned by ``yaw``; None when the pool is empty."""
        slot = next((s for s in self.slots if s.state is BoxState.PARKED), None)
        if slot is None:
            return None
        self._model.body_gravcomp[slot.body] = 0.0
        self._set_collision(slot, ENV_CONTYPE, ENV_CONAFFINITY)
        feed = self.feed_position if slot.size is None else self._feed_point(slot.size)
        data.qpos[slot.qpos : slot.qpos + 3] = feed + np.array([0.0, lateral, 0.0])
        data.qpos[slot.qpos + 3 : slot.qpos + 7] = (np.cos(yaw / 2), 0.0, 0.0, np.sin(yaw / 2))
        data.qvel[slot.qvel : slot.qvel + 6] = 0.0
        slot.state = BoxState.ACTIVE
        slot.released_at = t_sim
        return slot

    def active(self) -> list[BoxSlot]:
        return [s for s in self.slots if s.state is BoxState.ACTIVE]

    def position(self, data: mujoco.MjData, slot: BoxSlot) -> NDArray[np.float64]:
        return np.array(data.qpos[slot.qpos : slot.qpos + 3])

    def quaternion(self, data: mujoco.MjData, slot: BoxSlot) -> NDArray[np.float64]:
        return np.array(data.qpos[slot.qpos + 3 : slot.qpos + 7])

    def speed(self, data: mujoco.MjData, slot: BoxSlot) -> float:
        return float(np.linalg.norm(data.qvel[slot.qvel : slot.qvel + 3]))

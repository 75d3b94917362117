"""Grasp detection and the assisted grasp.

``physical``: boxes are held by the pads' contact and friction alone.
``assisted``: when both grippers are closed and both pads touch the same box, a weld
between the left hand and that box engages, keeping the box where it was relative to the
hand; opening either gripper releases it. Novices get a robust grasp; the contact signal
stays the same in both modes, so recordings are comparable.
"""

from __future__ import annotations

import mujoco
import numpy as np

from workcell.sim.arena import weld_name
from workcell.sim.boxes import BoxPool, BoxSlot
from workcell.sim.config import GraspMode

CLOSED = 0.5
"""A gripper whose close command is at least this is closed."""
CONTACT_MEMORY_S = 0.15
"""A pad counts as touching a box until this long after their last contact, so that
micro-slips of a physical squeeze grasp do not flicker the grasp signal."""


class Grasp:
    """Tracks which box each pad touches and, in assisted mode, the weld."""

    def __init__(self, model: mujoco.MjModel, pool: BoxPool, mode: GraspMode) -> None:
        self._model = model
        self._pool = pool
        self.mode: GraspMode = mode
        self._pads = (model.geom("pad_l").id, model.geom("pad_r").id)
        self._hand_l = model.body("hand_l").id
        self._welds = [model.equality(weld_name(s.index)).id for s in pool.slots]
        self._box_of_geom = {s.geom: s for s in pool.slots}
        self.contact_l: BoxSlot | None = None
        self.contact_r: BoxSlot | None = None
        self.attached: BoxSlot | None = None
        self._last_touch: list[tuple[BoxSlot | None, float]] = [(None, 0.0), (None, 0.0)]

    def reset(self, data: mujoco.MjData) -> None:
        data.eq_active[self._welds] = 0
        self.contact_l = self.contact_r = self.attached = None
        self._last_touch = [(None, 0.0), (None, 0.0)]

    @property
    def holding(self) -> BoxSlot | None:
        """The welded box (assisted) or the box both pads touch (physical)."""
        if self.mode == "assisted":
            return self.attached
        if self.contact_l is not None and self.contact_l is self.contact_r:
            return self.contact_l
        return None

    def update(
        self, data: mujoco.MjData, close_l: float, close_r: float
    ) -> tuple[BoxSlot, bool] | None:
        """Refresh contacts and the weld; returns (box, engaged) when the grasp changed."""
        before = self.holding
        self._refresh_contacts(data)
        if self.mode == "assisted":
            closed = close_l >= CLOSED and close_r >= CLOSED
            if self.attached is not None and not closed:
                data.eq_active[self._welds[self.attached.index]] = 0
                self.attached = None
            elif self.attached is None and closed:
                both = self.contact_l
                if both is not None and both is self.contact_r:
                    self._engage(data, both)
        after = self.holding
        if after is before:
            return None
        if after is None:
            assert before is not None
            return before, False
        return after, True

    def _refresh_contacts(self, data: mujoco.MjData) -> None:
        now = float(data.time)
        if data.ncon:
            # A plain loop over the few contacts (a handful to a few dozen): at every
            # physics step, NumPy's per-call cost would be most of the work.
            pads = self._pads
            for g1, g2 in data.contact.geom.tolist():
                for side, pad in enumerate(pads):
                    if pad in (g1, g2):
                        slot = self._box_of_geom.get(g2 if g1 == pad else g1)
                        if slot is not None:
                            self._last_touch[side] = (slot, now)
        touching = [
            slot if slot is not None and now - when <= CONTACT_MEMORY_S else None
            for slot, when in self._last_touch
        ]
        self.contact_l, self.contact_r = touching

    def _engage(self, data: mujoco.MjData, slot: BoxSlot) -> None:
        """Weld ``slot`` to the left hand at their current relative pose."""
        hand_pos, hand_quat = data.xpos[self._hand_l], data.xquat[self._hand_l]
        box_pos, box_quat = data.xpos[slot.body], data.xquat[slot.body]
        inv = np.zeros(4)
        mujoco.mju_negQuat(inv, hand_quat)
        rel_pos = np.zeros(3)
        mujoco.mju_rotVecQuat(rel_pos, box_pos - hand_pos, inv)
        rel_quat = np.zeros(4)
        mujoco.mju_mulQuat(rel_quat, inv, box_quat)
        eq = self._welds[slot.index]
        self._model.eq_data[eq, 0:3] = 0.0
        self._model.eq_data[eq, 3:6] = rel_pos
        self._model.eq_data[eq, 6:10] = rel_quat
        self._model.eq_data[eq, 10] = 1.0
        self._model.eq_data[eq, 11] = 0.0
        data.eq_active[eq] = 1
        self.attached = slot

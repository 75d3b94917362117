"""Where a trial's pallet stands and where its four slots are, read from the trial's
conditions, so the scene, the judge, the expert and the recorded goal agree.

The pallet is a platform on a stand beside the conveyor's end, its long sides facing the two
places the robot stands to set boxes down: the slots form a 2x2 pattern, two on the
pallet's -x half (reached from its -x side) and two on its +x half (reached from its +x
side). Along the approach the two rows sit close (:data:`ROW_GAP`); across it the two
boxes of a row leave room for a palm between them (:data:`PALM_GAP`), which the second
box of each row needs as it is set down beside the first. Each slot is anchored at the
pallet's outer edges (:data:`EDGE_MARGIN` in from them), so a trial's smaller boxes leave
wider gaps and the layout moves with the box size.

The pallet moves with the trial's drawn target shift (the delivery table's, which palletize
does not use otherwise) and turns with the drawn turn of the robot's start: both are in the
recorded conditions, so a recorded trial's pallet is known again without its scene.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from workcell.sim.config import WorldConfig, longest_box, widest_box

PALLET_CENTER = (2.0, -1.9)
"""The pallet's centre (x, y in the world, m) in the nominal world (D0)."""
PALLET_HEIGHT = 0.4
"""Height of the pallet's top above the floor (m): where a placed box's bottom rests. A
pallet on a stand: the arms set a box's centre no lower than about 0.45 m in front of the
base (measured: lower palm targets stall there), so a floor pallet (0.15 m) is out of
their reach."""
EDGE_MARGIN = 0.04
"""From a slot's outer sides to the pallet's edges (m)."""
ROW_GAP = 0.04
"""Between the two rows of the largest boxes, along the approach (m)."""
PALM_GAP = 0.30
"""Between the two boxes of a row of the largest boxes, across the approach (m): room for
a palm (a pad and its finger) and for opening it as it lets go."""
SLOT_TOLERANCE = 0.05
"""How far (m, in x and in y of the pallet) a box's centre may sit from its slot's centre
to count as in the slot."""
HEIGHT_TOLERANCE = 0.03
"""How far (m) a box's centre may sit from its resting height on the pallet."""
SLOT_SIGNS: tuple[tuple[float, float], ...] = ((-1.0, 1.0), (-1.0, -1.0), (1.0, 1.0), (1.0, -1.0))
"""The slots in the order the expert fills them (signs in the pallet frame): the -x row
first, from +y, then the +x row."""


def pallet_half_size(config: WorldConfig) -> tuple[float, float]:
    """Half the pallet's top in x and y (m): room for the largest boxes a trial of
    ``config`` can draw, two by two, with the gaps and margins."""
    along, across = longest_box(config), widest_box(config)
    return (along + ROW_GAP / 2 + EDGE_MARGIN, across + PALM_GAP / 2 + EDGE_MARGIN)


@dataclass(frozen=True)
class PalletLayout:
    """A trial's pallet: ``center`` (x, y), ``yaw`` (rad), ``half`` (half its top in its
    own x and y), the box ``size`` the slots are laid out for, and ``height`` of its top."""

    center: tuple[float, float]
    yaw: float
    half: tuple[float, float]
    size: tuple[float, float, float]
    height: float = PALLET_HEIGHT

    @staticmethod
    def of(conditions: Mapping[str, Any], config: WorldConfig) -> PalletLayout:
        """The pallet of a trial whose recorded ``conditions`` these are (the configured
        world where they say nothing)."""
        target = _pair(conditions.get("target_center"), config.target.center)
        start = conditions.get("start_pose")
        turn = 0.0
        if isinstance(start, Sequence) and len(start) == 3:
            turn = float(start[2]) - config.robot.start_pose[2]
        size = conditions.get("box_size")
        box = (
            (float(size[0]), float(size[1]), float(size[2]))
            if isinstance(size, Sequence) and len(size) == 3
            else config.box.size
        )
        shift = (target[0] - config.target.center[0], target[1] - config.target.center[1])
        return PalletLayout(
            center=(PALLET_CENTER[0] + shift[0], PALLET_CENTER[1] + shift[1]),
            yaw=turn,
            half=pallet_half_size(config),
            size=box,
        )

    @property
    def rest_z(self) -> float:
        """Height of a box's centre resting on the pallet."""
        return self.height + self.size[2] / 2

    def slot_local(self, index: int) -> tuple[float, float]:
        """Slot ``index``'s centre in the pallet's frame (m)."""
        sx, sy = SLOT_SIGNS[index]
        return (
            sx * (self.half[0] - EDGE_MARGIN - self.size[0] / 2),
            sy * (self.half[1] - EDGE_MARGIN - self.size[1] / 2),
        )

    def slot_center(self, index: int) -> NDArray[np.float64]:
        """Slot ``index``'s centre (x, y) in the world."""
        return self.to_world(np.array(self.slot_local(index)))

    def slot_centers(self) -> list[NDArray[np.float64]]:
        return [self.slot_center(i) for i in range(len(SLOT_SIGNS))]

    def to_world(self, local: NDArray[np.float64]) -> NDArray[np.float64]:
        c, s = math.cos(self.yaw), math.sin(self.yaw)
        return np.array(
            [
                self.center[0] + c * local[0] - s * local[1],
                self.center[1] + s * local[0] + c * local[1],
            ]
        )

    def to_local(self, world_xy: NDArray[np.float64]) -> NDArray[np.float64]:
        c, s = math.cos(self.yaw), math.sin(self.yaw)
        dx, dy = float(world_xy[0]) - self.center[0], float(world_xy[1]) - self.center[1]
        return np.array([c * dx + s * dy, -s * dx + c * dy])

    def slot_of(self, position: NDArray[np.float64]) -> int | None:
        """The slot whose footprint (plus :data:`SLOT_TOLERANCE`) holds a box centred at
        ``position`` (x, y, z) resting on the pallet, or None."""
        if abs(float(position[2]) - self.rest_z) > HEIGHT_TOLERANCE:
            return None
        local = self.to_local(position[:2])
        for index in range(len(SLOT_SIGNS)):
            sx, sy = self.slot_local(index)
            if abs(local[0] - sx) <= SLOT_TOLERANCE and abs(local[1] - sy) <= SLOT_TOLERANCE:
                return index
        return None


def _pair(value: object, default: tuple[float, float]) -> tuple[float, float]:
    if isinstance(value, Sequence) and len(value) == 2:
        return float(value[0]), float(value[1])
    return default

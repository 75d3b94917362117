"""The shelf unit shelve adds to the factory, and where a trial puts it.

Three bays side by side along x, each one board open above at its own height (bottom,
middle, top: :data:`BOARD_TOPS`), the unit's front facing +y, toward the delivery table the
box starts on. A board open above lets the robot bring the box in at the board's height and
set it down without an upper board in the way of its hands; the spine and the arms' reach
give the height. The unit stands at :data:`SHELF_CENTER`, moved in x and y per trial by up
to the world's ``randomization.target_shift`` (as the table is), and the asked board
carries a green strip along its front edge.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import mujoco
import numpy as np
from numpy.typing import NDArray

from workcell.sim.looks import DECOR_PREFIX, add_decor
from workcell.sim.spec_utils import set_env_collision

BOX = mujoco.mjtGeom.mjGEOM_BOX

SHELF_NAMES: tuple[str, ...] = ("bottom", "middle", "top")
"""The boards by index, as the instruction names them."""
BOARD_TOPS: tuple[float, ...] = (0.55, 0.85, 1.15)
"""Height (m) of each board's top face."""
BAY_OFFSETS: tuple[float, ...] = (-0.85, 0.0, 0.85)
"""Each bay's centre along x from the unit's centre (m)."""
BAY_WIDTH = 0.6
"""Width of a board along x (m). The gaps between boards (0.25 m) leave room for the
wrists beside a box set down on a board below its neighbour."""
BAY_DEPTH = 0.5
"""Depth of a board along y (m)."""
BOARD_THICKNESS = 0.03
SHELF_CENTER: tuple[float, float] = (1.6, -1.9)
"""Where the unit stands in D0: across the conveyor's line from the delivery table."""
POST_HALF = 0.02
MARK_OFF_RGBA = (0.3, 0.3, 0.32, 1.0)
MARK_ON_RGBA = (0.2, 0.75, 0.35, 1.0)
BOARD_RGBA = (0.8, 0.45, 0.1, 1.0)
POST_RGBA = (0.2, 0.35, 0.7, 1.0)


def board_name(index: int) -> str:
    return f"shelf_board_{index}"


def mark_name(index: int) -> str:
    """The name :func:`build_shelf` gives a board's strip (decor is named with a prefix)."""
    return f"shelf_mark_{index}"


@dataclass(frozen=True)
class ShelfLayout:
    """One trial's shelf: where the unit stands (``center``, x and y) and which board the
    trial asks for (``asked``, an index of :data:`SHELF_NAMES`)."""

    center: tuple[float, float]
    asked: int

    @staticmethod
    def nominal() -> ShelfLayout:
        return ShelfLayout(SHELF_CENTER, len(SHELF_NAMES) - 1)

    @staticmethod
    def draw(rng: np.random.Generator, shift: float) -> ShelfLayout:
        """A trial's shelf: a board drawn evenly, the unit moved up to ``shift`` in x, y."""
        asked = int(rng.integers(len(SHELF_NAMES)))
        dx, dy = (float(rng.uniform(-shift, shift)) for _ in range(2))
        return ShelfLayout((SHELF_CENTER[0] + dx, SHELF_CENTER[1] + dy), asked)

    def recorded(self) -> dict[str, float | tuple[float, ...]]:
        """What the trial's conditions record under ``task``."""
        return {"shelf": self.asked, "shelf_center": self.center}

    @staticmethod
    def from_recorded(task: Mapping[str, Any] | None) -> ShelfLayout:
        """The layout :meth:`recorded` wrote (the nominal one where it says nothing)."""
        nominal = ShelfLayout.nominal()
        if not isinstance(task, Mapping):
            return nominal
        center, asked = task.get("shelf_center"), task.get("shelf")
        if not (isinstance(center, list | tuple) and len(center) == 2):
            return nominal
        if not (
            isinstance(asked, int | float)
            and float(asked).is_integer()
            and int(asked) in range(len(SHELF_NAMES))
        ):
            return nominal
        return ShelfLayout((float(center[0]), float(center[1])), int(asked))

    @property
    def asked_name(self) -> str:
        return SHELF_NAMES[self.asked]

    def board_center(self, index: int) -> NDArray[np.float64]:
        """x, y of a board's centre in the world."""
        return np.array([self.center[0] + BAY_OFFSETS[index], self.center[1]])

    def board_top(self, index: int) -> float:
        return BOARD_TOPS[index]

    def on_board(self, index: int, position: NDArray[np.float64], box_height: float) -> bool:
        """Whether a box centred at ``position`` sits on board ``index``: its centre over
        the board and its bottom on the board's top (within 2 cm)."""
        x, y = self.board_center(index)
        over = abs(position[0] - x) <= BAY_WIDTH / 2 and abs(position[1] - y) <= BAY_DEPTH / 2
        level = abs(position[2] - (BOARD_TOPS[index] + box_height / 2)) < 0.02
        return bool(over and level)


def build_shelf(spec: mujoco.MjSpec) -> None:
    """Add the unit (body ``shelf``, at the nominal centre) to ``spec``."""
    unit = spec.worldbody.add_body(name="shelf", pos=[SHELF_CENTER[0], SHELF_CENTER[1], 0])
    for i, (x, top) in enumerate(zip(BAY_OFFSETS, BOARD_TOPS, strict=True)):
        board = unit.add_geom(
            name=board_name(i),
            type=BOX,
            size=[BAY_WIDTH / 2, BAY_DEPTH / 2, BOARD_THICKNESS / 2],
            pos=[x, 0, top - BOARD_THICKNESS / 2],
            rgba=list(BOARD_RGBA),
            material="painted_steel",
            friction=[1.0, 0.005, 0.0001],
        )
        set_env_collision(board)
        # Posts under the board's back corners only: its front and sides stay open.
        for sx in (1.0, -1.0):
            post = unit.add_geom(
                type=BOX,
                size=[POST_HALF, POST_HALF, (top - BOARD_THICKNESS) / 2],
                pos=[
                    x + sx * (BAY_WIDTH / 2 - POST_HALF),
                    -BAY_DEPTH / 2 + POST_HALF,
                    (top - BOARD_THICKNESS) / 2,
                ],
                rgba=list(POST_RGBA),
                material="painted_steel",
            )
            set_env_collision(post)
        add_decor(
            unit,
            mark_name(i),
            BOX,
            [BAY_WIDTH / 2 - 0.02, 0.02, 0.002],
            rgba=MARK_OFF_RGBA,
            material="painted_steel",
            pos=[x, BAY_DEPTH / 2 - 0.04, top + 0.002],
        )


def place_shelf(model: mujoco.MjModel, layout: ShelfLayout) -> None:
    """Stand the unit where ``layout`` says and light the asked board's strip."""
    model.body_pos[model.body("shelf").id, :2] = layout.center
    for i in range(len(SHELF_NAMES)):
        rgba = MARK_ON_RGBA if i == layout.asked else MARK_OFF_RGBA
        model.geom_rgba[model.geom(DECOR_PREFIX + mark_name(i)).id] = rgba

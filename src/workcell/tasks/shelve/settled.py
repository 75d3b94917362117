"""Shelve's settled check: the box the trial shelved stays on the asked board.

Data generation runs the simulation on for a second after a success
(:mod:`workcell.generate.recheck`) and asks each control period whether the box that was
resting on the asked board when the trial succeeded still rests there, released and
still. A box that slides off, tips over the board's edge or is taken up again makes the
success a false one.
"""

from __future__ import annotations

from workcell.sim.boxes import BoxSlot
from workcell.sim.world import World
from workcell.tasks.shelve.judge import resting_on_asked_board
from workcell.tasks.shelve.shelf import ShelfLayout
from workcell.tasks.shelve.stages import REST_SPEED


class ShelvedBoxStays:
    """Watches the box ``world``'s trial had shelved when it succeeded."""

    def __init__(self, world: World) -> None:
        self._layout = ShelfLayout.from_recorded(world.conditions.task_values)
        self._watched: BoxSlot | None = resting_on_asked_board(world, self._layout)

    @property
    def objects(self) -> int:
        return int(self._watched is not None)

    def why_undone(self, world: World, settling: bool) -> str | None:
        slot = self._watched
        if slot is None:
            return None
        if world.grasp.holding is slot:
            return f"box {slot.index} held again"
        position = world.boxes.position(world.data, slot)
        height = world.conditions.box_size[2]
        if not self._layout.on_board(self._layout.asked, position, height):
            return f"box {slot.index} off the {self._layout.asked_name} board"
        speed = world.boxes.speed(world.data, slot)
        if not settling and speed >= REST_SPEED:
            return f"box {slot.index} moving ({speed:.2f} m/s) on the board"
        return None

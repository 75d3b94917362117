"""Sort's settled check: nothing sorted is undone, and nothing is missorted after.

A box counts as sorted only once it has rested released in its own kind's zone for a whole
second (:data:`~workcell.tasks.sort.scene.SORTED_S`), and the scene then takes it away, so a
sorted box cannot slide or be knocked off later: sort's success is settled when it is made.
Data generation still runs the simulation on for a second after a success
(:mod:`workcell.generate.recheck`) with the generated operator acting; a box it set down in
the other kind's zone meanwhile (the pool is refilled once every box is sorted) undoes it.
"""

from __future__ import annotations

from workcell.sim.world import World
from workcell.tasks.sort.judge import sort_scene


class SortedStay:
    """Watches ``world``'s sort scene from the moment its trial succeeded."""

    def __init__(self, world: World) -> None:
        scene = sort_scene(world)
        self._sorted = scene.sorted_count
        self._missorted = set(scene.missorted)

    @property
    def objects(self) -> int:
        return self._sorted

    def why_undone(self, world: World, settling: bool) -> str | None:
        added = sorted(sort_scene(world).missorted - self._missorted)
        if added:
            return f"box {added[0]} set down in the other kind's zone"
        return None

"""Sort's expert: box transfer's, setting each box down on its own kind's table."""

from __future__ import annotations

import numpy as np

from workcell.sim.boxes import BoxSlot
from workcell.sim.world import World
from workcell.tasks.elements.expert import ExpertOperator, Placement
from workcell.tasks.sort.judge import sort_scene


class SortExpert(ExpertOperator):
    """Carries each box to the centre of its kind's zone."""

    def placement(self, world: World, box: BoxSlot) -> Placement:
        center = sort_scene(world).layout.table_of(box.index)
        rest_z = world.config.target.table_height + world.boxes.size_of(box)[2] / 2
        return Placement(np.array(center), rest_z)

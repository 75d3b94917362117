"""Judging a sort trial as it runs: success once the boxes asked for are sorted (each
rested released in its own kind's zone for a second, :mod:`workcell.tasks.sort.scene`);
failure once a box rested as long in the other kind's zone."""

from __future__ import annotations

from workcell.sim.events import BoxCompleted, WorldEvent
from workcell.sim.world import World
from workcell.tasks.sort.scene import SortScene, zone_under
from workcell.tasks.sort.stages import SortStageTracker
from workcell.tasks.task import Evaluation


def sort_scene(world: World) -> SortScene:
    """The world's sort scene (a judge or expert of sort needs one)."""
    scene = world.scene
    if not isinstance(scene, SortScene):
        raise RuntimeError("a sort trial needs the world built with the sort task's scene")
    return scene


class SortJudge:
    """A trial that must sort ``required`` boxes."""

    def __init__(self, required: int) -> None:
        self.required = required
        self._sorted = 0
        self._tracker = SortStageTracker()

    @property
    def done(self) -> int:
        return self._sorted

    def observe(self, event: WorldEvent) -> None:
        if isinstance(event, BoxCompleted):
            self._sorted += 1

    def evaluate(self, world: World) -> Evaluation:
        scene = sort_scene(world)
        tracker = self._tracker
        grasp = world.grasp
        if grasp.contact_l is not None or grasp.contact_r is not None:
            tracker.touch()
        held = grasp.holding
        if held is None:
            tracker.release()
        else:
            position = world.boxes.position(world.data, held)
            table = zone_under(world.config, scene.layout, position)
            own = table is not None and table == scene.layout.kind_of(held.index)
            tracker.hold(held.index, float(position[2]), own)
        failure = bool(scene.missorted)
        return Evaluation(
            success=self._sorted >= self.required and not failure,
            failure=failure,
            progress=min(1.0, self._sorted / self.required),
            stage=tracker.stage(self._sorted, self.required),
        )

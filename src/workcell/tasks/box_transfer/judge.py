"""Judging a box-transfer trial as it runs: the one success rule (its boxes delivered) and
the stage reached, read from the world at each frame instant as the recorder samples it."""

from __future__ import annotations

from workcell.sim.events import BoxCompleted, WorldEvent
from workcell.sim.world import World
from workcell.tasks.box_transfer.stages import Hold, StageTracker, Zone
from workcell.tasks.task import Evaluation


class BoxTransferJudge:
    """A trial that must deliver ``required`` boxes: it succeeds when they are delivered
    (a box is delivered once it rests in the zone released, :mod:`workcell.sim.target`)."""

    def __init__(self, required: int) -> None:
        self.required = required
        self._delivered = 0
        self._tracker: StageTracker | None = None
        self._frame = 0

    @property
    def done(self) -> int:
        return self._delivered

    def observe(self, event: WorldEvent) -> None:
        if isinstance(event, BoxCompleted):
            self._delivered += 1

    def evaluate(self, world: World) -> Evaluation:
        tracker = self._tracker
        if tracker is None:
            zone = world.zone
            center = (float(zone.center[0]), float(zone.center[1]))
            size = (float(2 * zone.half[0]), float(2 * zone.half[1]))
            tracker = self._tracker = StageTracker(Zone(center, size))
        grasp = world.grasp
        if grasp.contact_l is not None or grasp.contact_r is not None:
            tracker.touch()
        held = grasp.holding
        if held is not None:
            x, y, z = (float(v) for v in world.boxes.position(world.data, held))
            tracker.hold(Hold(self._frame, held.index, x, y, z))
        self._frame += 1
        stage = tracker.stage(self._delivered)
        return Evaluation(
            success=self._delivered >= self.required,
            failure=False,
            progress=min(1.0, self._delivered / self.required),
            stage=stage,
        )

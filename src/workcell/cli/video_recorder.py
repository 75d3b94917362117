"""Samples a running simulation onto an MP4 at a fixed frame rate of simulated time."""

from __future__ import annotations

from pathlib import Path

from workcell.closing import Closing
from workcell.control.simulation import Simulation
from workcell.render import OffscreenRenderer, VideoWriter, overview_camera


class VideoRecorder(Closing):
    """Call after each control step; writes a frame whenever the next frame time is due."""

    def __init__(self, sim: Simulation, path: Path, size: tuple[int, int], fps: int) -> None:
        width, height = size
        self._renderer = OffscreenRenderer(sim.world.model, width, height, shadows=False)
        self._writer = VideoWriter(path, width, height, fps)
        self._camera = overview_camera(sim.world.model)
        self._period = 1.0 / fps
        self._next = 0.0

    def __call__(self, sim: Simulation) -> None:
        while sim.time + 1e-9 >= self._next:
            self._writer.write(self._renderer.render(sim.world.data, self._camera))
            self._next += self._period

    def close(self) -> None:
        """Finish the MP4 and free the renderer."""
        self._writer.close()
        self._renderer.close()

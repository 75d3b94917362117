"""A world that replays recorded frames: replay check, MuJoCo states and camera images.

Camera images are rendered from the restored states with shadows and reflections off
(see :class:`workcell.render.OffscreenRenderer`), a few milliseconds per image on a
software renderer. One world (and one OpenGL context) serves every trial recorded under
the same world configuration: :class:`WorldPool`.
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence

import numpy as np
from numpy.typing import NDArray

from workcell.closing import Closing
from workcell.export.errors import ReplayMismatchError
from workcell.export.options import ImageSize
from workcell.export.replay import TCP_TOLERANCE_M, ReplayErrors, replay_errors
from workcell.export.restore import RecordedStates, StateRestorer
from workcell.render.quality import CAMERA_QUALITY
from workcell.render.renderer import OffscreenRenderer
from workcell.session.config import SessionConfig
from workcell.sim.config import WorldConfig
from workcell.sim.world import World
from workcell.tasks.registry import load_task


class ReplayWorld:
    """One world configuration, restoring recorded frames into its MuJoCo state."""

    def __init__(self, config: SessionConfig, size: ImageSize | None = None) -> None:
        self.world = World(config.world, load_task(config.task.kind).scene())
        self.restorer = StateRestorer(self.world)
        self.size = size
        self._renderer: OffscreenRenderer | None = None

    def check(self, states: RecordedStates, trial_id: str) -> ReplayErrors:
        """The replay check of one trial's frames; raises when it fails."""
        errors = replay_errors(self.world, states)
        if not errors.within_tolerance:
            raise ReplayMismatchError(
                f"trial {trial_id}: restoring its recorded states misses the recorded TCP "
                f"poses by {errors.position_m:.3g} m and {errors.angle_rad:.3g} rad "
                f"(tolerance {TCP_TOLERANCE_M:g}); this world model is not the one that "
                "recorded it: use the Workcell version that recorded the store"
            )
        return errors

    def mujoco_states(self, states: RecordedStates) -> NDArray[np.float64]:
        """(frames, nq + nv): the restored ``qpos`` and ``qvel`` of every frame."""
        data = self.world.data
        rows = []
        for i in range(len(states)):
            self.restorer.restore(states, i, forward=False)
            rows.append(np.concatenate([data.qpos, data.qvel]))
        return np.array(rows).reshape(len(states), -1)

    def images(
        self, states: RecordedStates, cameras: Sequence[str]
    ) -> Iterator[dict[str, NDArray[np.uint8]]]:
        """Per frame, one (height, width, 3) RGB image per camera."""
        renderer = self._open_renderer()
        for i in range(len(states)):
            self.restorer.restore(states, i)
            yield renderer.render_all(self.world.data, cameras)

    def _open_renderer(self) -> OffscreenRenderer:
        if self._renderer is None:
            size = self.size or ImageSize()
            self._renderer = OffscreenRenderer(
                self.world.model, size.width, size.height, quality=CAMERA_QUALITY
            )
        return self._renderer

    def close(self) -> None:
        if self._renderer is not None:
            self._renderer.close()
            self._renderer = None


class WorldPool(Closing):
    """One :class:`ReplayWorld` per world configuration, created when first needed."""

    def __init__(self, size: ImageSize | None = None) -> None:
        self.size = size
        self._worlds: dict[tuple[str, WorldConfig], ReplayWorld] = {}

    def get(self, config: SessionConfig) -> ReplayWorld:
        """The replay world of ``config``'s task and world."""
        key = (config.task.kind, config.world)
        if key not in self._worlds:
            self._worlds[key] = ReplayWorld(config, self.size)
        return self._worlds[key]

    def close(self) -> None:
        for world in self._worlds.values():
            world.close()
        self._worlds.clear()

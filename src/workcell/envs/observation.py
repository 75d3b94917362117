"""Observations in LeRobot's gym convention, built as the exports build their features.

An observation is a dict, as gym-aloha's and gym-pusht's are:

- ``agent_pos`` (float32, 39): the robot, the export's ``observation.state``
  (:data:`workcell.export.features.STATE_NAMES`);
- ``environment_state`` (float32, 8 per box, the task's goal, then both relative to the
  robot): every box, then what the trial asks (box transfer: its target zone's centre),
  then the boxes and the goal's points in the base frame and the boxes from each gripper
  (:mod:`workcell.export.relative`), the export's
  ``observation.environment_state`` (:func:`workcell.export.boxes.environment_names`);
- ``pixels`` (only with cameras): ``{camera: uint8 (height, width, 3)}``, channel last,
  the export's ``observation.images.<camera>`` before LeRobot scales it to [0, 1] CHW.

``lerobot.envs.utils.preprocess_observation`` turns one into exactly the features a
policy trained on an export reads (same names, shapes and order). The values come from
the recorder's own frame builder (:class:`workcell.recording.frame_format.FrameReader`), so
they mean what the recorded columns mean, continuous quaternions included; images are
rendered as the exports render them (shadows and reflections off).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from workcell.control.command import Command
from workcell.control.simulation import Simulation
from workcell.export.boxes import parse_boxes
from workcell.export.features import STATE_NAMES
from workcell.export.options import ImageSize
from workcell.export.relative import relative_features
from workcell.recording.frame_format import FrameReader
from workcell.render.quality import CAMERA_QUALITY
from workcell.render.renderer import OffscreenRenderer
from workcell.tasks import Task

AGENT_POS = "agent_pos"
ENVIRONMENT_STATE = "environment_state"
PIXELS = "pixels"

Observation = dict[str, Any]
"""``agent_pos`` and ``environment_state`` (float32 arrays), ``pixels`` (a dict of uint8 images)."""


class ObservationBuilder:
    """Observations of one simulation, frame after frame of one episode until
    :meth:`restart`. Renders only when ``cameras`` are asked for."""

    def __init__(
        self,
        sim: Simulation,
        task: Task,
        cameras: Sequence[str] = (),
        size: ImageSize | None = None,
    ) -> None:
        self.sim = sim
        self.task = task
        self.cameras = tuple(cameras)
        self.size = size or ImageSize()
        self.pool_size = sim.config.feeder.pool_size
        self._reader = FrameReader(sim.world, sim.controller)
        self._renderer: OffscreenRenderer | None = None
        self._goal = np.zeros(len(task.goal_names))

    def restart(self) -> None:
        """The next observation is the first of a new episode (whose world was reset: its
        goal is read from the trial's conditions now)."""
        self._reader.restart()
        conditions = self.sim.world.conditions.as_dict()
        self._goal = np.array(self.task.goal(conditions, self.sim.config), dtype=np.float64)

    def observe(self, command: Command) -> Observation:
        """The observation of the world now; ``command`` is the latest one given (it is
        part of a recorded frame, not of the observation)."""
        row = self._reader.read(command, None, t_sim=0.0, t_wall=0.0, step_wall_ms=0.0)
        state = np.array([[row[name] for name in STATE_NAMES]], dtype=np.float64)
        boxes = parse_boxes([row["boxes"]], self.pool_size)
        relative = relative_features(state, boxes.poses, self._goal[None, :], self.task.goal_names)
        environment = np.concatenate([boxes.features()[0], self._goal, relative[0]])
        observation: Observation = {
            AGENT_POS: state[0].astype(np.float32),
            ENVIRONMENT_STATE: environment.astype(np.float32),
        }
        if self.cameras:
            observation[PIXELS] = self._images()
        return observation

    def _images(self) -> dict[str, NDArray[np.uint8]]:
        if self._renderer is None:
            model = self.sim.world.model
            self._renderer = OffscreenRenderer(
                model, self.size.width, self.size.height, quality=CAMERA_QUALITY
            )
        data = self.sim.world.data
        return self._renderer.render_all(data, self.cameras)

    def close(self) -> None:
        """Free the renderer (if any); observing again makes a new one."""
        if self._renderer is not None:
            self._renderer.close()
            self._renderer = None

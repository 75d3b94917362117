"""The conditions one trial runs under: the configured ones, or drawn from the trial's seed
within the ranges of :class:`~workcell.sim.randomization.RandomizationConfig`, applied
without recompiling and recorded with the trial."""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from workcell.sim.config import WorldConfig

TaskValue = float | tuple[float, ...]
"""One value a task's scene draws for a trial: a number or a few."""


@dataclass(frozen=True)
class TrialConditions:
    """The conditions one trial runs under (the configured ones unless randomized)."""

    box_size: tuple[float, float, float]
    box_mass: float
    box_rgba: tuple[float, float, float, float]
    conveyor_speed: float
    release_interval_s: float
    target_center: tuple[float, float]
    start_pose: tuple[float, float, float]
    task: tuple[tuple[str, TaskValue], ...] = ()
    """What the task's scene drew for this trial (``name``, value pairs: which shelf, where
    the shelf stands), set by :meth:`with_task` from the scene's reset; recorded under
    ``task`` only when there is something (box transfer's scene draws nothing)."""

    @staticmethod
    def nominal(config: WorldConfig) -> TrialConditions:
        return TrialConditions(
            box_size=config.box.size,
            box_mass=config.box.mass,
            box_rgba=config.box.rgba,
            conveyor_speed=config.conveyor.speed,
            release_interval_s=config.feeder.release_interval_s,
            target_center=config.target.center,
            start_pose=config.robot.start_pose,
        )

    @staticmethod
    def draw(config: WorldConfig, rng: np.random.Generator) -> TrialConditions:
        """This trial's conditions; the nominal ones when randomization is off."""
        r = config.randomization
        nominal = TrialConditions.nominal(config)
        if not r.enabled:
            return nominal

        def scaled(value: float, fraction: float) -> float:
            return float(value * (1.0 + rng.uniform(-fraction, fraction)))

        def shifted(values: tuple[float, ...], amount: float) -> list[float]:
            return [float(v + rng.uniform(-amount, amount)) for v in values]

        size = tuple(scaled(s, r.box_size) for s in nominal.box_size)
        rgba = [min(1.0, max(0.0, c)) for c in shifted(nominal.box_rgba[:3], r.box_colour)]
        x, y = shifted(nominal.target_center, r.target_shift)
        sx, sy = shifted(nominal.start_pose[:2], r.start_shift)
        yaw = nominal.start_pose[2] + float(rng.uniform(-r.start_yaw, r.start_yaw))
        return TrialConditions(
            box_size=(size[0], size[1], size[2]),
            box_mass=scaled(nominal.box_mass, r.box_mass),
            box_rgba=(rgba[0], rgba[1], rgba[2], nominal.box_rgba[3]),
            conveyor_speed=scaled(nominal.conveyor_speed, r.conveyor_speed),
            release_interval_s=scaled(nominal.release_interval_s, r.release_interval),
            target_center=(x, y),
            start_pose=(sx, sy, yaw),
        )

    def with_task(self, values: Mapping[str, TaskValue]) -> TrialConditions:
        """These conditions with what the task's scene drew (``values``)."""
        return dataclasses.replace(self, task=tuple(values.items()))

    @property
    def task_values(self) -> dict[str, TaskValue]:
        """What the task's scene drew, by name ({}: nothing)."""
        return dict(self.task)

    def as_dict(self) -> dict[str, Any]:
        """JSON-ready values, recorded with the trial (the task's draw under ``task``, and
        only when it drew something)."""
        values = {
            k: list(v) if isinstance(v, tuple) else v
            for k, v in dataclasses.asdict(self).items()
            if k != "task"
        }
        if self.task:
            values["task"] = {k: list(v) if isinstance(v, tuple) else v for k, v in self.task}
        return values

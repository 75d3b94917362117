"""What the environment simulates: a session configuration and the task of an episode."""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any, Literal, get_args

from workcell.errors import ConfigError
from workcell.export.options import ROBOT_CAMERAS, ImageSize
from workcell.session.config import SessionConfig
from workcell.session.toml_io import from_mapping
from workcell.settings import divides, steps_per
from workcell.sim.randomization import RandomizationConfig
from workcell.tasks import Task, WorldName

RewardKind = Literal["deliveries", "staged"]
REWARD_KINDS: tuple[str, ...] = get_args(RewardKind)


@dataclass(frozen=True)
class BoxTransferConfig:
    """The world, frame rate and countdown come from ``session``; an episode ends when
    ``required_boxes`` are delivered (terminated) or at the time limit (truncated).
    ``cameras`` adds their images to every observation (``pixels``) at ``camera_size``;
    ``render_camera`` and ``render_size`` are what :meth:`render` shows. ``reward``:
    ``deliveries`` (1.0 per box delivered) or ``staged`` (each stage of the task reached
    earns its share, the episode's rewards summing to 1.0 at the last stage)."""

    session: SessionConfig = field(default_factory=SessionConfig)
    required_boxes: int = 1
    time_limit_s: float | None = None
    """Seconds of sim time per episode; None: the session's ``task.time_limit_s``."""
    cameras: tuple[str, ...] = ()
    camera_size: ImageSize = field(default_factory=lambda: ImageSize(128, 128))
    render_camera: str = "head_cam"
    render_size: ImageSize = field(default_factory=ImageSize)
    reward: RewardKind = "deliveries"

    def __post_init__(self) -> None:
        problems: list[str] = []
        if self.reward not in REWARD_KINDS:
            problems.append(f"reward = {self.reward!r}: must be one of {', '.join(REWARD_KINDS)}")
        pool = self.session.world.feeder.pool_size
        if type(self.required_boxes) is not int or not 1 <= self.required_boxes <= pool:
            problems.append(
                f"required_boxes = {self.required_boxes!r}: must be 1 to the pool size {pool}"
            )
        limit = self.time_limit_s
        if limit is not None and not (math.isfinite(limit) and limit > 0):
            problems.append(f"time_limit_s = {limit!r}: must be > 0 seconds (or None)")
        unknown = [c for c in self.cameras if c not in ROBOT_CAMERAS]
        if unknown or len(set(self.cameras)) != len(self.cameras):
            problems.append(
                f"cameras = {self.cameras!r}: must be distinct names among "
                f"{', '.join(ROBOT_CAMERAS)}"
            )
        if self.render_camera not in ROBOT_CAMERAS:
            problems.append(
                f"render_camera = {self.render_camera!r}: must be one of {', '.join(ROBOT_CAMERAS)}"
            )
        problems += divides(
            "recording.sampling_rate_hz",
            self.session.recording.sampling_rate_hz,
            self.session.world.robot.control_hz,
            "the control rate world.robot.control_hz",
            whole=True,
        )
        if problems:
            raise ConfigError(problems)

    @classmethod
    def from_parameters(cls, parameters: Mapping[str, Any], **options: Any) -> BoxTransferConfig:
        """The environment of a recorded session: ``parameters`` as a store keeps them
        (``SessionRecord.parameters``); ``options`` are the other fields."""
        return cls(session=from_mapping(SessionConfig, parameters), **options)

    def for_task(self, kind: str) -> BoxTransferConfig:
        """This configuration with the task ``kind`` (a ``task.kind``) in place of its own."""
        session = self.session
        task = dataclasses.replace(session.task, kind=kind)
        return dataclasses.replace(self, session=dataclasses.replace(session, task=task))

    def in_world(self, task: Task, world: WorldName) -> BoxTransferConfig:
        """This configuration in ``task``'s world ``world`` (its randomization ranges)."""
        ranges = RandomizationConfig(**task.worlds[world])
        session = self.session
        world_config = dataclasses.replace(session.world, randomization=ranges)
        return dataclasses.replace(self, session=dataclasses.replace(session, world=world_config))

    @property
    def episode_session(self) -> SessionConfig:
        """The session an episode is a trial of: one trial of ``limit_s``."""
        task = dataclasses.replace(self.session.task, mode="practice", time_limit_s=self.limit_s)
        return dataclasses.replace(self.session, task=task)

    @property
    def fps(self) -> int:
        return round(self.session.recording.sampling_rate_hz)

    @property
    def control_steps_per_frame(self) -> int:
        """Control steps per recorded frame (validated to be whole on construction)."""
        steps = steps_per(
            self.session.world.robot.control_hz, self.session.recording.sampling_rate_hz
        )
        assert steps is not None, "validated in __post_init__"
        return steps

    @property
    def limit_s(self) -> float:
        return self.session.task.time_limit_s if self.time_limit_s is None else self.time_limit_s

    @property
    def max_episode_steps(self) -> int:
        """Steps (frames) in an episode that reaches the time limit."""
        return math.ceil(self.limit_s * self.fps - 1e-9)

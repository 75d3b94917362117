"""Frozen, validated configuration of the world and the robot.

Every dataclass checks its own fields on construction and raises :class:`ConfigError` with
one line per problem, so an invalid world is rejected before any simulation starts.
Lengths are metres, angles radians, times seconds, masses kilograms.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Literal, get_args

from workcell.errors import ConfigError
from workcell.sim import checks

GraspMode = Literal["assisted", "physical"]
GRASP_MODES: tuple[str, ...] = get_args(GraspMode)


def _raise_if(problems: list[str]) -> None:
    if problems:
        raise ConfigError(problems)


@dataclass(frozen=True)
class ConveyorConfig:
    """A straight belt along +x that ends at ``end_x`` against a stop bar."""

    speed: float = 0.2
    length: float = 3.0
    width: float = 0.5
    height: float = 0.75
    end_x: float = 0.0
    center_y: float = 0.0

    def __post_init__(self) -> None:
        _raise_if(
            checks.in_range("conveyor.speed", self.speed, 0.01, 1.0, "m/s")
            + checks.in_range("conveyor.length", self.length, 1.0, 10.0, "m")
            + checks.in_range("conveyor.width", self.width, 0.2, 1.5, "m")
            + checks.in_range("conveyor.height", self.height, 0.4, 1.1, "m")
            + checks.in_range("conveyor.end_x", self.end_x, -4.0, 4.0, "m")
            + checks.in_range("conveyor.center_y", self.center_y, -4.0, 4.0, "m")
        )

    @property
    def start_x(self) -> float:
        return self.end_x - self.length

    @property
    def direction_yaw(self) -> float:
        """Heading of the belt's motion in the world (the belt runs along +x)."""
        return 0.0


@dataclass(frozen=True)
class FeederConfig:
    """Boxes wait parked in a pool and are released onto the belt start at an interval."""

    release_interval_s: float = 8.0
    first_release_s: float = 0.5
    pool_size: int = 4
    lateral_jitter: float = 0.04
    """Boxes land up to this far (m) either side of the belt centre line, seeded."""
    yaw_jitter: float = 0.15
    """Boxes land turned up to this much (rad) either way, seeded."""

    def __post_init__(self) -> None:
        problems = (
            checks.in_range("feeder.release_interval_s", self.release_interval_s, 0.5, 600.0, "s")
            + checks.in_range("feeder.first_release_s", self.first_release_s, 0.0, 600.0, "s")
            + checks.in_range("feeder.lateral_jitter", self.lateral_jitter, 0.0, 0.2, "m")
            + checks.in_range("feeder.yaw_jitter", self.yaw_jitter, 0.0, 0.5, "rad")
        )
        if type(self.pool_size) is not int or not 1 <= self.pool_size <= 12:
            problems.append(checks.problem("feeder.pool_size", self.pool_size, "must be 1 to 12"))
        _raise_if(problems)


@dataclass(frozen=True)
class BoxConfig:
    """``size`` is (along the belt, across the belt, height); the grasp axis is across."""

    size: tuple[float, float, float] = (0.3, 0.3, 0.3)
    mass: float = 2.0
    rgba: tuple[float, float, float, float] = (0.78, 0.58, 0.35, 1.0)

    def __post_init__(self) -> None:
        problems = checks.length("box.size", self.size, 3)
        problems += checks.in_range("box.mass", self.mass, 0.05, 10.0, "kg")
        if len(self.size) == 3 and not all(0.05 <= side <= 0.6 for side in self.size):
            problems.append(
                checks.problem("box.size", self.size, "every side must be between 0.05 and 0.6 m")
            )
        problems += checks.length("box.rgba", self.rgba, 4)
        if len(self.rgba) == 4 and not all(0.0 <= c <= 1.0 for c in self.rgba):
            problems.append(checks.problem("box.rgba", self.rgba, "components must be in [0, 1]"))
        _raise_if(problems)


@dataclass(frozen=True)
class TargetConfig:
    """The delivery table; a box resting inside ``zone`` on its top, released, is delivered."""

    center: tuple[float, float] = (1.6, 1.9)
    table_height: float = 0.6
    zone: tuple[float, float] = (0.7, 0.7)

    def __post_init__(self) -> None:
        problems = checks.length("target.center", self.center, 2) + checks.finite(
            "target.center", self.center
        )
        problems += checks.in_range("target.table_height", self.table_height, 0.2, 1.1, "m")
        problems += checks.length("target.zone", self.zone, 2)
        if len(self.zone) == 2 and not all(0.2 <= z <= 2.0 for z in self.zone):
            problems.append(checks.problem("target.zone", self.zone, "sides must be 0.2 to 2 m"))
        finite = all(math.isfinite(c) for c in self.center)
        if len(self.center) == 2 and finite and not all(abs(c) <= 5.0 for c in self.center):
            problems.append(checks.problem("target.center", self.center, "must lie within 5 m"))
        _raise_if(problems)


@dataclass(frozen=True)
class RobotConfig:
    """Limits and start pose of the mobile bimanual robot."""

    max_linear_speed: float = 0.8
    max_yaw_rate: float = 1.2
    linear_accel: float = 1.5
    yaw_accel: float = 3.0
    start_pose: tuple[float, float, float] = (1.4, 0.0, math.pi)
    start_spine: float = 0.1
    max_grasp_span: float = 0.55
    control_hz: float = 40.0

    def __post_init__(self) -> None:
        problems = (
            checks.in_range("robot.max_linear_speed", self.max_linear_speed, 0.05, 2.0, "m/s")
            + checks.in_range("robot.max_yaw_rate", self.max_yaw_rate, 0.1, 4.0, "rad/s")
            + checks.in_range("robot.linear_accel", self.linear_accel, 0.1, 10.0, "m/s^2")
            + checks.in_range("robot.yaw_accel", self.yaw_accel, 0.1, 20.0, "rad/s^2")
            + checks.length("robot.start_pose", self.start_pose, 3)
            + checks.finite("robot.start_pose", self.start_pose)
            + checks.in_range("robot.start_spine", self.start_spine, 0.0, 0.35, "m")
            + checks.in_range("robot.max_grasp_span", self.max_grasp_span, 0.2, 0.7, "m")
            + checks.in_range("robot.control_hz", self.control_hz, 10.0, 200.0, "Hz")
        )
        _raise_if(problems)


@dataclass(frozen=True)
class WorldConfig:
    """Everything that defines a world; a session parameter set stores one of these."""

    conveyor: ConveyorConfig = field(default_factory=ConveyorConfig)
    feeder: FeederConfig = field(default_factory=FeederConfig)
    box: BoxConfig = field(default_factory=BoxConfig)
    target: TargetConfig = field(default_factory=TargetConfig)
    robot: RobotConfig = field(default_factory=RobotConfig)
    grasp: GraspMode = "assisted"
    timestep: float = 0.0025

    def __post_init__(self) -> None:
        problems = checks.one_of("grasp", self.grasp, GRASP_MODES)
        timestep_problems = checks.in_range("timestep", self.timestep, 0.0005, 0.005, "s")
        problems += timestep_problems
        across = self.box.size[1]
        if across > self.robot.max_grasp_span:
            problems.append(
                checks.problem(
                    "box.size",
                    self.box.size,
                    f"the width across the belt ({across:g} m) must not exceed the span the "
                    f"grippers can reach around, robot.max_grasp_span = "
                    f"{self.robot.max_grasp_span:g} m",
                )
            )
        room = self.conveyor.width - 0.04 - 2 * self.feeder.lateral_jitter
        if across > room:
            problems.append(
                checks.problem(
                    "box.size",
                    self.box.size,
                    f"the width across the belt must be at most conveyor.width - 0.04 - "
                    f"2 * feeder.lateral_jitter = {room:g} m",
                )
            )
        if self.box.size[0] * 1.5 > self.conveyor.length:
            problems.append(
                checks.problem("box.size", self.box.size, "must be shorter than the conveyor")
            )
        substeps = 1.0 / (self.robot.control_hz * self.timestep) if not timestep_problems else 1
        if substeps < 1.0 - 1e-9 or abs(substeps - round(substeps)) > 1e-6:
            problems.append(
                checks.problem(
                    "robot.control_hz",
                    self.robot.control_hz,
                    f"must divide the physics rate 1/timestep = {1 / self.timestep:g} Hz "
                    "into a whole number of physics steps",
                )
            )
        if _target_overlaps_conveyor(self.target, self.conveyor, margin=0.3):
            problems.append(
                checks.problem(
                    "target.center",
                    self.target.center,
                    "the delivery zone must keep 0.3 m clear of the conveyor footprint "
                    f"(x {self.conveyor.start_x:g}..{self.conveyor.end_x:g}, "
                    f"y {self.conveyor.center_y - self.conveyor.width / 2:g}.."
                    f"{self.conveyor.center_y + self.conveyor.width / 2:g})",
                )
            )
        _raise_if(problems)

    @property
    def control_substeps(self) -> int:
        """Physics steps per control step."""
        return max(1, round(1.0 / (self.robot.control_hz * self.timestep)))


def _target_overlaps_conveyor(
    target: TargetConfig, conveyor: ConveyorConfig, margin: float
) -> bool:
    half_x, half_y = target.zone[0] / 2 + margin, target.zone[1] / 2 + margin
    tx, ty = target.center
    x_overlap = tx + half_x > conveyor.start_x - 0.1 and tx - half_x < conveyor.end_x + 0.1
    y_lo, y_hi = conveyor.center_y - conveyor.width / 2, conveyor.center_y + conveyor.width / 2
    y_overlap = ty + half_y > y_lo and ty - half_y < y_hi
    return x_overlap and y_overlap

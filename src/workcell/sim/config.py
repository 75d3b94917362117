"""Frozen, validated configuration of the world and the robot.

Every dataclass checks its own fields on construction and raises :class:`ConfigError` with
one line per problem, so an invalid world is rejected before any simulation starts. A
problem names its field by the section the class fills (``conveyor.speed``,
``world.grasp``), the way the TOML file spells it below its parent table.
Lengths are metres, angles radians, times seconds, masses kilograms.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal, get_args

from workcell import checks
from workcell.errors import ConfigError
from workcell.settings import section, setting
from workcell.sim.randomization import RandomizationConfig

GraspMode = Literal["assisted", "physical"]
GRASP_MODES: tuple[str, ...] = get_args(GraspMode)


def _raise_if(problems: list[str]) -> None:
    if problems:
        raise ConfigError(problems)


@dataclass(frozen=True)
class ConveyorConfig:
    """A straight belt along +x that ends at ``end_x`` against a stop bar."""

    speed: float = setting(0.2, "belt speed, m/s (0.01 to 1)")
    length: float = setting(3.0, "belt length, m (1 to 10)")
    width: float = setting(0.5, "belt width, m (0.2 to 1.5)")
    height: float = setting(0.75, "height of the belt surface, m (0.4 to 1.1)")
    end_x: float = setting(0.0, "x of the belt's end stop in the world, m (-4 to 4)")
    center_y: float = setting(0.0, "y of the belt's centre line, m (-4 to 4)")

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

    release_interval_s: float = setting(8.0, "seconds between box releases (0.5 to 600)")
    first_release_s: float = setting(
        0.5, "seconds after a reset until the first release (0 to 600)"
    )
    pool_size: int = setting(4, "boxes in the pool the feeder draws from (1 to 12)")
    lateral_jitter: float = setting(
        0.04, "boxes land up to this far either side of the centre line, m (0 to 0.2), seeded"
    )
    yaw_jitter: float = setting(
        0.15, "boxes land turned up to this much either way, rad (0 to 0.5), seeded"
    )

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

    size: tuple[float, float, float] = setting(
        (0.3, 0.3, 0.3), "along the belt, across the belt (the grasp axis), height; m (0.05 to 0.6)"
    )
    mass: float = setting(2.0, "box mass, kg (0.05 to 10)")
    rgba: tuple[float, float, float, float] = setting(
        (0.78, 0.58, 0.35, 1.0), "box colour, red green blue alpha (0 to 1 each)"
    )

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

    center: tuple[float, float] = setting(
        (1.6, 1.9), "x, y of the delivery zone's centre, m; must keep 0.3 m clear of the conveyor"
    )
    table_height: float = setting(0.6, "height of the delivery table top, m (0.2 to 1.1)")
    zone: tuple[float, float] = setting((0.7, 0.7), "size of the delivery zone, m (0.2 to 2 each)")

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

    max_linear_speed: float = setting(0.8, "base speed limit, m/s (0.05 to 2)")
    max_yaw_rate: float = setting(1.2, "base turn-rate limit, rad/s (0.1 to 4)")
    linear_accel: float = setting(1.5, "base acceleration limit, m/s^2 (0.1 to 10)")
    yaw_accel: float = setting(3.0, "base angular acceleration limit, rad/s^2 (0.1 to 20)")
    start_pose: tuple[float, float, float] = setting(
        (1.4, 0.0, math.pi), "x, y (m) and yaw (rad) of the base at every reset"
    )
    start_spine: float = setting(0.1, "spine height at reset, m (0 to 0.35)")
    max_grasp_span: float = setting(
        0.55, "widest box the two palms can close around, m (0.2 to 0.7)"
    )
    control_hz: float = setting(
        40.0, "control and IK rate, Hz; must divide the physics rate 1/timestep evenly"
    )

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

    conveyor: ConveyorConfig = section(ConveyorConfig, "the belt that brings the boxes")
    feeder: FeederConfig = section(FeederConfig, "how and when boxes are released")
    box: BoxConfig = section(BoxConfig, "the boxes")
    target: TargetConfig = section(TargetConfig, "the delivery table and its zone")
    robot: RobotConfig = section(RobotConfig, "the mobile bimanual robot")
    randomization: RandomizationConfig = section(
        RandomizationConfig, "per-trial domain randomization (off: every range 0)"
    )
    grasp: GraspMode = setting(
        "assisted", "assisted (a weld holds a box both closed grippers touch) or physical"
    )
    timestep: float = setting(0.0025, "physics timestep, s (0.0005 to 0.005)")

    def __post_init__(self) -> None:
        problems = checks.one_of("world.grasp", self.grasp, GRASP_MODES)
        timestep_problems = checks.in_range("world.timestep", self.timestep, 0.0005, 0.005, "s")
        problems += timestep_problems
        across = widest_box(self)
        if across > self.robot.max_grasp_span:
            problems.append(
                checks.problem(
                    "world.box.size",
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
                    "world.box.size",
                    self.box.size,
                    f"the width across the belt must be at most conveyor.width - 0.04 - "
                    f"2 * feeder.lateral_jitter = {room:g} m",
                )
            )
        if longest_box(self) * 1.5 > self.conveyor.length:
            problems.append(
                checks.problem("world.box.size", self.box.size, "must be shorter than the conveyor")
            )
        substeps = 1.0 / (self.robot.control_hz * self.timestep) if not timestep_problems else 1
        if substeps < 1.0 - 1e-9 or abs(substeps - round(substeps)) > 1e-6:
            problems.append(
                checks.problem(
                    "world.robot.control_hz",
                    self.robot.control_hz,
                    f"must divide the physics rate 1/timestep = {1 / self.timestep:g} Hz "
                    "into a whole number of physics steps",
                )
            )
        shift = self.randomization.target_shift
        if _target_overlaps_conveyor(self.target, self.conveyor, margin=0.3 + shift):
            problems.append(
                checks.problem(
                    "world.target.center",
                    self.target.center,
                    f"the delivery zone must keep 0.3 m (+ randomization.target_shift = "
                    f"{shift:g} m) clear of the conveyor footprint "
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


def widest_box(config: WorldConfig) -> float:
    """The widest box (across the belt) a trial can draw."""
    return config.box.size[1] * (1.0 + config.randomization.box_size)


def longest_box(config: WorldConfig) -> float:
    """The longest box (along the belt) a trial can draw."""
    return config.box.size[0] * (1.0 + config.randomization.box_size)

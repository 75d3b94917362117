"""Frozen, validated configuration of the world and the robot.

Every field is declared once with :func:`~workcell.settings.setting` (default, unit,
allowed values, meaning). Every dataclass checks its fields against those declarations,
and its cross-field rules, on construction and raises :class:`ConfigError` with one line
per problem, so an invalid world is rejected before any simulation starts. A
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
from workcell.settings import declared_problems, divides, section, setting, steps_per
from workcell.sim.randomization import RandomizationConfig

GraspMode = Literal["assisted", "physical"]
GRASP_MODES: tuple[str, ...] = get_args(GraspMode)


def _raise_if(problems: list[str]) -> None:
    if problems:
        raise ConfigError(problems)


@dataclass(frozen=True)
class ConveyorConfig:
    """A straight belt along +x that ends at ``end_x`` against a stop bar."""

    speed: float = setting(0.2, "belt speed", unit="m/s", low=0.01, high=1.0)
    length: float = setting(3.0, "belt length", unit="m", low=1.0, high=10.0)
    width: float = setting(0.5, "belt width", unit="m", low=0.2, high=1.5)
    height: float = setting(0.75, "height of the belt surface", unit="m", low=0.4, high=1.1)
    end_x: float = setting(0.0, "x of the belt's end stop in the world", unit="m", low=-4, high=4)
    center_y: float = setting(0.0, "y of the belt's centre line", unit="m", low=-4.0, high=4.0)

    def __post_init__(self) -> None:
        _raise_if(declared_problems(self, "conveyor"))

    @property
    def start_x(self) -> float:
        return self.end_x - self.length

    @property
    def direction_yaw(self) -> float:
        """Heading of the belt's motion in the world (the belt runs along +x)."""
        return 0.0

    @property
    def obstacle(self) -> tuple[tuple[float, float, float], tuple[float, float, float]]:
        """The box the arms keep clear of (the IK's proxy of the belt and its frame): its
        centre in the world and its half sizes."""
        center = ((self.start_x + self.end_x) / 2, self.center_y, (0.15 + self.height) / 2)
        return center, (self.length / 2, self.width / 2 + 0.03, (self.height - 0.15) / 2)


@dataclass(frozen=True)
class FeederConfig:
    """Boxes wait parked in a pool and are released onto the belt start at an interval."""

    release_interval_s: float = setting(
        8.0, "time between box releases", unit="s", low=0.5, high=600.0
    )
    first_release_s: float = setting(
        0.5, "time after a reset until the first release", unit="s", low=0.0, high=600.0
    )
    pool_size: int = setting(
        4, "boxes in the pool the feeder draws from", unit="boxes", low=1, high=12
    )
    lateral_jitter: float = setting(
        0.04,
        "boxes land up to this far either side of the centre line (seeded)",
        unit="m",
        low=0.0,
        high=0.2,
    )
    yaw_jitter: float = setting(
        0.15, "boxes land turned up to this much either way (seeded)", unit="rad", low=0.0, high=0.5
    )

    def __post_init__(self) -> None:
        _raise_if(declared_problems(self, "feeder"))


@dataclass(frozen=True)
class BoxConfig:
    """``size`` is (along the belt, across the belt, height); the grasp axis is across."""

    size: tuple[float, float, float] = setting(
        (0.3, 0.3, 0.3),
        "box sides: along the belt, across the belt (the grasp axis), height",
        unit="m",
        low=0.05,
        high=0.6,
        length=3,
    )
    mass: float = setting(2.0, "box mass", unit="kg", low=0.05, high=10.0)
    rgba: tuple[float, float, float, float] = setting(
        (0.78, 0.58, 0.35, 1.0),
        "box colour: red, green, blue, alpha",
        unit="1",
        low=0.0,
        high=1.0,
        length=4,
    )

    def __post_init__(self) -> None:
        _raise_if(declared_problems(self, "box"))


@dataclass(frozen=True)
class TargetConfig:
    """The delivery table; a box resting inside ``zone`` on its top, released, is delivered."""

    center: tuple[float, float] = setting(
        (1.6, 1.9),
        "x, y of the delivery zone's centre",
        unit="m",
        low=-5.0,
        high=5.0,
        length=2,
        constraint="the zone must keep 0.3 m clear of the conveyor",
    )
    table_height: float = setting(
        0.6, "height of the delivery table top", unit="m", low=0.2, high=1.1
    )
    zone: tuple[float, float] = setting(
        (0.7, 0.7), "size of the delivery zone in x and y", unit="m", low=0.2, high=2.0, length=2
    )

    def __post_init__(self) -> None:
        _raise_if(declared_problems(self, "target"))


@dataclass(frozen=True)
class RobotConfig:
    """Limits and start pose of the mobile bimanual robot."""

    max_linear_speed: float = setting(0.8, "base speed limit", unit="m/s", low=0.05, high=2.0)
    max_yaw_rate: float = setting(1.2, "base turn-rate limit", unit="rad/s", low=0.1, high=4.0)
    linear_accel: float = setting(1.5, "base acceleration limit", unit="m/s^2", low=0.1, high=10.0)
    yaw_accel: float = setting(
        3.0, "base angular acceleration limit", unit="rad/s^2", low=0.1, high=20.0
    )
    start_pose: tuple[float, float, float] = setting(
        (1.4, 0.0, math.pi),
        "x, y and yaw of the base at every reset, inside the walls at +-5 m",
        unit="m, m, rad",
        low=-5.0,
        high=5.0,
        length=3,
    )
    start_spine: float = setting(0.1, "spine height at reset", unit="m", low=0.0, high=0.35)
    human_clearance: float = setting(
        0.05,
        "a base driven by a person's sticks slows early enough to stop this far from the "
        "conveyor, the table and the walls (0: off); the expert and policies are not slowed",
        unit="m",
        low=0.0,
        high=1.0,
    )
    max_grasp_span: float = setting(
        0.55, "widest box the two palms can close around", unit="m", low=0.2, high=0.7
    )
    control_hz: float = setting(
        40.0,
        "control rate (and the IK's, unless ik_hz says otherwise)",
        unit="Hz",
        low=10.0,
        high=200.0,
        constraint="must divide the physics rate 1/world.timestep evenly",
    )
    teleop_control_hz: float = setting(
        100.0,
        "control rate while a person drives (workcell serve): their input acts "
        "within one period of arriving, 10 ms at 100 Hz; the expert and policies run at "
        "control_hz",
        unit="Hz",
        low=10.0,
        high=200.0,
        constraint="must divide the physics rate 1/world.timestep evenly",
    )
    ik_hz: float = setting(
        0.0,
        "how often the IK solves for the arms' joint targets (0: every control period); in "
        "the periods between two solves the arms move on at the last solved joint "
        "velocities, so a lower rate costs less CPU and follows new targets a little later",
        unit="Hz",
        low=0.0,
        high=200.0,
        constraint="0, or a rate that divides world.robot.control_hz evenly",
    )
    teleop_ik_hz: float = setting(
        0.0,
        "how often the IK solves while a person drives (workcell serve), as ik_hz (0: every "
        "control period at teleop_control_hz)",
        unit="Hz",
        low=0.0,
        high=200.0,
        constraint="0, or a rate that divides world.robot.teleop_control_hz evenly",
    )

    def __post_init__(self) -> None:
        problems = declared_problems(self, "robot")
        if not problems:
            for ik, control in (("ik_hz", "control_hz"), ("teleop_ik_hz", "teleop_control_hz")):
                if getattr(self, ik) > 0:
                    problems += divides(  # named within the section, as the others
                        f"robot.{ik}",
                        getattr(self, ik),
                        getattr(self, control),
                        f"the control rate {control}",
                    )
        _raise_if(problems)

    @property
    def ik_every(self) -> int:
        """Control periods per IK solve: 1 when ``ik_hz`` is 0 (validated whole)."""
        if self.ik_hz <= 0:
            return 1
        steps = steps_per(self.control_hz, self.ik_hz)
        assert steps is not None, "validated in __post_init__"
        return steps


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
        "assisted",
        "assisted: a weld holds a box both closed grippers touch; physical: contact and "
        "friction alone",
    )
    timestep: float = setting(0.0025, "physics timestep", unit="s", low=0.0005, high=0.005)

    def __post_init__(self) -> None:
        problems = declared_problems(self, "world")
        timestep_problems = [p for p in problems if p.startswith("world.timestep ")]
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
        if not timestep_problems:
            for name in ("control_hz", "teleop_control_hz"):
                problems += divides(
                    f"world.robot.{name}",
                    getattr(self.robot, name),
                    1.0 / self.timestep,
                    "the physics rate 1/world.timestep",
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
    def physics_hz(self) -> float:
        return 1.0 / self.timestep

    @property
    def control_substeps(self) -> int:
        """Physics steps per control step (validated to be whole on construction)."""
        steps = steps_per(self.physics_hz, self.robot.control_hz)
        assert steps is not None, "validated in __post_init__"
        return steps

    @property
    def arm_obstacle(self) -> tuple[tuple[float, float, float], tuple[float, float, float]]:
        """The fixed box the arms keep clear of: its centre in the world, its half sizes."""
        return self.conveyor.obstacle


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

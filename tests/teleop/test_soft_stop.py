"""The soft stop, in the real world: full stick at the conveyor or the table stops the
base short of it; with the stop off the same input drives into it; driving away is not
slowed."""

from __future__ import annotations

import dataclasses
import math

import mujoco
import pytest

from workcell.control.simulation import Simulation
from workcell.protocol.messages import ControllerState, Input
from workcell.sim.config import WorldConfig
from workcell.teleop.config import TeleopConfig
from workcell.teleop.operator import TeleopOperator
from workcell.teleop.soft_stop import SoftStop, fixed_obstacles

TOWARDS_CONVEYOR = (0.0, 1.0)  # the robot starts facing the conveyor's end
TOWARDS_TABLE = (1.0, 0.0)  # strafing right from the start heads for the table


def _hand(stick: tuple[float, float]) -> ControllerState:
    return ControllerState(
        pose=(0.2, 1.1, -0.3, 1.0, 0.0, 0.0, 0.0), grip=0.0, trigger=0.0, stick=stick, buttons=0
    )


class Drive:
    """A real simulation driven by a teleoperator holding the left stick."""

    def __init__(self, clearance: float) -> None:
        config = WorldConfig()
        robot = dataclasses.replace(config.robot, human_clearance=clearance)
        self.config = dataclasses.replace(config, robot=robot)
        self.sim = Simulation(self.config)
        self.now = 0.0
        self.operator = TeleopOperator(
            TeleopConfig(),
            clock=lambda: self.now,
            soft_stop=SoftStop(self.sim.world.model, robot),
        )
        self.seq = 0
        model = self.sim.world.model
        self.obstacles = set(fixed_obstacles(model))
        self.chassis = model.geom("chassis").id
        self.touched: set[str] = set()
        self.nearest = math.inf

    def hold(self, stick: tuple[float, float], seconds: float) -> None:
        model, data = self.sim.world.model, self.sim.world.data
        for _ in range(round(seconds / self.sim.control_dt)):
            self.now += self.sim.control_dt
            self.seq += 1
            message = Input(
                seq=self.seq,
                t_client=0.0,
                source="xr",
                headset=None,
                left=_hand(stick),
                right=_hand((0.0, 0.0)),
            )
            self.operator.submit(message)
            self.sim.step(self.operator.act(self.sim.world))
            for contact in data.contact[: data.ncon]:
                pair = {int(contact.geom1), int(contact.geom2)}
                if self.chassis in pair and pair & self.obstacles:
                    self.touched |= {model.geom((pair - {self.chassis}).pop()).name or "?"}
            distances = [
                mujoco.mj_geomDistance(model, data, self.chassis, g, 2.0, None)
                for g in self.obstacles
            ]
            self.nearest = min(self.nearest, *distances)

    @property
    def speed(self) -> float:
        return float(math.hypot(*self.sim.world.base_velocity[:2]))


@pytest.mark.parametrize("stick", [TOWARDS_CONVEYOR, TOWARDS_TABLE], ids=["conveyor", "table"])
def test_full_stick_at_an_obstacle_stops_short_of_it(stick: tuple[float, float]) -> None:
    off = Drive(clearance=0.0)
    off.hold(stick, 3.0)
    assert off.touched, "without the soft stop the base should have hit the obstacle"
    on = Drive(clearance=WorldConfig().robot.human_clearance)
    on.hold(stick, 3.0)
    assert not on.touched
    assert 0.01 <= on.nearest <= on.config.robot.human_clearance
    assert on.speed < 0.02  # stopped, though the stick is still held


def test_driving_away_from_an_obstacle_is_not_slowed() -> None:
    drive = Drive(clearance=0.05)
    drive.hold(TOWARDS_CONVEYOR, 3.0)
    drive.hold((0.0, -1.0), 1.5)
    assert drive.speed > 0.95 * drive.config.robot.max_linear_speed
    assert not drive.touched


def test_a_wider_clearance_stops_farther_away() -> None:
    near, far = Drive(clearance=0.05), Drive(clearance=0.3)
    near.hold(TOWARDS_CONVEYOR, 3.0)
    far.hold(TOWARDS_CONVEYOR, 3.0)
    assert far.nearest > near.nearest + 0.2
    assert far.nearest <= 0.3


def test_the_clearance_is_a_checked_setting() -> None:
    from workcell.errors import ConfigError
    from workcell.sim.config import RobotConfig

    with pytest.raises(ConfigError, match="human_clearance"):
        RobotConfig(human_clearance=-0.1)
    with pytest.raises(ConfigError, match="human_clearance"):
        RobotConfig(human_clearance=float("nan"))

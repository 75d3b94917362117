"""Snap turns in the real world: one request turns the base by the snap angle on the sim
clock (whatever the control rate), the stick's own turn is overridden meanwhile, and stale
input cancels a snap (the base stops)."""

from __future__ import annotations

import dataclasses
import math

import pytest

from workcell.control.simulation import Simulation
from workcell.protocol.messages import ControllerState, Input
from workcell.sim.config import WorldConfig
from workcell.teleop.config import TeleopConfig
from workcell.teleop.operator import TeleopOperator
from workcell.teleop.snap_turn import SNAP_ANGLE

HAND = ControllerState(
    pose=(0.2, 1.1, -0.3, 1.0, 0.0, 0.0, 0.0), grip=0.0, trigger=0.0, stick=(0.0, 0.0), buttons=0
)


class Turning:
    """A real simulation and a teleoperator whose sticks rest (or turn with ``right_x``)."""

    def __init__(self, control_hz: float = 100.0) -> None:
        config = WorldConfig()
        self.config = dataclasses.replace(
            config, robot=dataclasses.replace(config.robot, control_hz=control_hz)
        )
        self.sim = Simulation(self.config)
        self.now = 0.0
        base = self.sim.controller.base
        self.operator = TeleopOperator(
            TeleopConfig(),
            clock=lambda: self.now,
            heading_source=lambda _world: (float(base.pose[2]), float(base.twist[2])),
        )
        self.seq = 0

    @property
    def yaw(self) -> float:
        return float(self.sim.world.base_pose[2])

    def run(self, seconds: float, right_x: float = 0.0, fresh: bool = True) -> None:
        right = dataclasses.replace(HAND, stick=(right_x, 0.0))
        for _ in range(round(seconds / self.sim.control_dt)):
            self.now += self.sim.control_dt
            if fresh:
                self.seq += 1
                message = Input(self.seq, 0.0, "xr", None, HAND, right)
                assert self.operator.submit(message)
            self.sim.step(self.operator.act(self.sim.world))


def _turned(before: float, after: float) -> float:
    return math.atan2(math.sin(after - before), math.cos(after - before))


@pytest.mark.parametrize(("direction", "control_hz"), [(1, 100.0), (-1, 100.0), (1, 40.0)])
def test_a_snap_turns_the_base_by_the_snap_angle_and_stops(
    direction: int, control_hz: float
) -> None:
    world = Turning(control_hz)
    world.run(0.2)
    before = world.yaw
    world.operator.ask_snap(direction)
    world.run(2.0)
    turned = _turned(before, world.yaw)
    assert turned == pytest.approx(direction * SNAP_ANGLE, abs=math.radians(2.0))
    assert world.operator.snap is None  # over
    assert abs(float(world.sim.world.base_velocity[2])) < 0.05


def test_a_snap_overrides_the_stick_and_stale_input_cancels_it() -> None:
    world = Turning()
    world.run(0.2)
    before = world.yaw
    world.operator.ask_snap(1)
    for _ in range(300):  # the stick turns right all along; the snap turns left
        world.run(world.sim.control_dt, right_x=1.0)
        if not _snapping(world.operator):
            break
    assert _turned(before, world.yaw) == pytest.approx(SNAP_ANGLE, abs=math.radians(3.0))

    world.run(0.5)  # stick at rest
    world.operator.ask_snap(-1)
    world.run(0.05)
    assert _snapping(world.operator)
    world.run(1.0, fresh=False)  # the link stalls: no input for 1 s
    assert not _snapping(world.operator)  # the base stopped instead of finishing the snap
    middle = world.yaw
    world.run(1.0)
    assert _turned(middle, world.yaw) == pytest.approx(0.0, abs=0.01)  # not resumed


def _snapping(operator: TeleopOperator) -> bool:
    return operator.snap is not None

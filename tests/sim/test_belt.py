"""The belt carries a released box at the configured speed, flat, onto the pickup plate."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pytest
from numpy.typing import NDArray

from workcell.control.command import Command
from workcell.control.simulation import Simulation
from workcell.sim.arena import pickup_plate_length, pickup_range_x
from workcell.sim.boxes import BoxState
from workcell.sim.config import ConveyorConfig, FeederConfig, WorldConfig

SPEEDS = (0.15, 0.3)
AT_STOP_S = 3.0
"""How long the recording continues after the box reached the pickup plate."""
CREEP_S = 6.0
"""Crossing from the belt onto the still plate takes a few seconds."""


@dataclass(frozen=True)
class BeltRun:
    config: WorldConfig
    t: NDArray[np.float64]
    pos: NDArray[np.float64]  # (n, 3)
    quat: NDArray[np.float64]  # (n, 4)
    vel: NDArray[np.float64]  # (n, 6): linear (world), angular
    released_at: float

    @property
    def pickup(self) -> tuple[float, float]:
        return pickup_range_x(self.config)

    def riding(self) -> NDArray[np.bool_]:
        """Samples on the belt: settled (1 s after release), 0.05 m before the plate."""
        belt_end = self.config.conveyor.end_x - pickup_plate_length(self.config)
        before_plate = self.pos[:, 0] < belt_end - self.config.box.size[0] / 2 - 0.05
        return (self.t > self.released_at + 1.0) & before_plate

    def at_stop(self) -> NDArray[np.bool_]:
        """Samples from 1 s after the box came fully onto the pickup plate."""
        arrived = np.flatnonzero(self.pos[:, 0] > self.pickup[0] - 0.005)
        assert arrived.size, "the box never reached the pickup plate"
        return np.asarray(self.t >= self.t[arrived[0]] + 1.0, dtype=np.bool_)


def tilt_deg(quat: NDArray[np.float64]) -> NDArray[np.float64]:
    """Angle between each box's z axis and the world's z axis, degrees."""
    x, y = quat[:, 1], quat[:, 2]
    zz = 1.0 - 2.0 * (x * x + y * y)  # R[2, 2]
    return np.asarray(np.degrees(np.arccos(np.clip(zz, -1.0, 1.0))), dtype=float)


@pytest.fixture(scope="module", params=SPEEDS, ids=[f"{s}mps" for s in SPEEDS])
def belt_run(request: pytest.FixtureRequest) -> BeltRun:
    speed = float(request.param)
    # The feeder's default placement (which may offset and turn the box) is kept on purpose:
    # every check below holds wherever on the belt start the box lands.
    config = WorldConfig(
        conveyor=ConveyorConfig(speed=speed),
        feeder=FeederConfig(first_release_s=0.5, pool_size=1),
    )
    sim = Simulation(config)
    world = sim.world
    slot = world.boxes.slots[0]
    rest_x = pickup_range_x(config)[0]
    travel = (rest_x - world.boxes.feed_position[0]) / speed
    end = config.feeder.first_release_s + travel + CREEP_S + AT_STOP_S
    t, pos, quat, vel = [], [], [], []
    released_at = np.nan
    while sim.time < end:
        for event in sim.step(Command()):
            released_at = event.t_sim
        if slot.state is BoxState.ACTIVE:
            t.append(sim.time)
            pos.append(world.boxes.position(world.data, slot))
            quat.append(world.boxes.quaternion(world.data, slot))
            vel.append(np.array(world.data.qvel[slot.qvel : slot.qvel + 6]))
    assert t, "the feeder never released the box"
    return BeltRun(
        config, np.array(t), np.array(pos), np.array(quat), np.array(vel), float(released_at)
    )


def test_box_rides_at_belt_speed(belt_run: BeltRun) -> None:
    speed = belt_run.config.conveyor.speed
    riding = belt_run.riding()
    assert riding.sum() > 50
    slope = np.polyfit(belt_run.t[riding], belt_run.pos[riding, 0], 1)[0]
    assert slope == pytest.approx(speed, rel=0.02)
    vx = belt_run.vel[riding, 0]
    assert np.all(np.abs(vx - speed) <= 0.02 * speed), (vx.min(), vx.max())


def test_box_rides_flat_and_straight(belt_run: BeltRun) -> None:
    """No tilt, no sideways drift, no turning, on the belt surface; the belt runs along +x."""
    riding = belt_run.riding()
    assert tilt_deg(belt_run.quat[riding]).max() < 0.1
    y = belt_run.pos[riding, 1]
    assert np.ptp(y) < 0.002
    conveyor = belt_run.config.conveyor
    assert abs(y[0] - conveyor.center_y) < conveyor.width / 2 - belt_run.config.box.size[1] / 2
    resting_z = conveyor.height + belt_run.config.box.size[2] / 2
    assert np.abs(belt_run.pos[riding, 2] - resting_z).max() < 0.002
    assert np.abs(belt_run.vel[riding, 1:3]).max() < 0.01
    assert np.abs(belt_run.vel[riding, 3:]).max() < 0.01
    quat = belt_run.quat[riding]
    assert np.abs(quat @ quat[0]).min() > 1 - 1e-6  # orientation unchanged while riding


def test_box_stops_on_the_pickup_plate(belt_run: BeltRun) -> None:
    stop = belt_run.at_stop()
    assert stop.sum() > 50
    x = belt_run.pos[stop, 0]
    low, high = belt_run.pickup
    assert np.all((x >= low - 0.005) & (x <= high)), (x.min(), x.max(), low, high)
    assert np.ptp(x) < 0.001
    assert tilt_deg(belt_run.quat[stop]).max() < 1.0
    conveyor = belt_run.config.conveyor
    half_room = conveyor.width / 2 - belt_run.config.box.size[1] / 2
    assert np.abs(belt_run.pos[stop, 1] - conveyor.center_y).max() < half_room


def test_box_on_the_pickup_plate_is_at_rest(belt_run: BeltRun) -> None:
    """Off the running belt, the box stays still: an expert or a human can wait for that."""
    stop = belt_run.at_stop()
    linear = np.linalg.norm(belt_run.vel[stop, :3], axis=1)
    angular = np.linalg.norm(belt_run.vel[stop, 3:], axis=1)
    assert linear.mean() < 0.01, f"mean {linear.mean():.3f} m/s, max {linear.max():.3f} m/s"
    assert angular.max() < 0.2, f"max angular speed {angular.max():.3f} rad/s"

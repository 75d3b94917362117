"""Base motion: speed and acceleration limits, exact integration of a constant twist."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from numpy.typing import NDArray

from workcell.control.base_motion import BaseMotion
from workcell.control.command import BaseTwist, Command
from workcell.control.simulation import Simulation
from workcell.sim.config import FeederConfig, RobotConfig, WorldConfig

DT = 0.02
CONFIG = RobotConfig()


def run(motion: BaseMotion, command: BaseTwist, steps: int) -> NDArray[np.float64]:
    """Twists after each step, (steps, 3)."""
    twists = []
    for _ in range(steps):
        motion.step(command, DT)
        twists.append(motion.twist.copy())
    return np.array(twists)


def fresh(pose: tuple[float, float, float] = (0.0, 0.0, 0.0)) -> BaseMotion:
    motion = BaseMotion(CONFIG)
    motion.reset(pose)
    return motion


@pytest.mark.parametrize(
    "command",
    [
        BaseTwist(vx=5.0),
        BaseTwist(vx=-5.0),
        BaseTwist(vy=3.0),
        BaseTwist(vx=2.0, vy=2.0),
        BaseTwist(wz=10.0),
        BaseTwist(vx=3.0, vy=-1.0, wz=-10.0),
    ],
    ids=["forward", "backward", "left", "diagonal", "turn", "all"],
)
def test_step_command_respects_speed_and_acceleration(command: BaseTwist) -> None:
    motion = fresh()
    twists = run(motion, command, 150)
    twists = np.vstack([np.zeros(3), twists, run(motion, BaseTwist(), 150)])  # and stop again
    speed = np.linalg.norm(twists[:, :2], axis=1)
    assert speed.max() <= CONFIG.max_linear_speed + 1e-12
    assert np.abs(twists[:, 2]).max() <= CONFIG.max_yaw_rate + 1e-12
    delta = np.diff(twists, axis=0)
    assert np.linalg.norm(delta[:, :2], axis=1).max() <= CONFIG.linear_accel * DT + 1e-12
    assert np.abs(delta[:, 2]).max() <= CONFIG.yaw_accel * DT + 1e-12
    # reaches the (clipped) command, keeping its direction
    peak = twists[150]
    wanted = np.array([command.vx, command.vy])
    if np.linalg.norm(wanted) > 0:
        expected = (
            wanted / np.linalg.norm(wanted) * min(np.linalg.norm(wanted), CONFIG.max_linear_speed)
        )
        np.testing.assert_allclose(peak[:2], expected, atol=1e-9)
    assert peak[2] == pytest.approx(np.clip(command.wz, -CONFIG.max_yaw_rate, CONFIG.max_yaw_rate))
    np.testing.assert_allclose(twists[-1], 0.0, atol=1e-12)


def test_pose_speed_matches_twist() -> None:
    """The reference pose moves no faster than the limited twist."""
    motion = fresh((1.0, 2.0, 0.5))
    poses = [motion.pose.copy()]
    for _ in range(100):
        poses.append(motion.step(BaseTwist(vx=4.0, vy=4.0, wz=4.0), DT).copy())
    steps = np.diff(np.array(poses), axis=0) / DT
    assert np.linalg.norm(steps[:, :2], axis=1).max() <= CONFIG.max_linear_speed + 1e-9
    assert np.abs(steps[:, 2]).max() <= CONFIG.max_yaw_rate + 1e-9


def analytic_pose(
    start: NDArray[np.float64], twist: tuple[float, float, float], t: float
) -> NDArray[np.float64]:
    """Pose after ``t`` seconds of a constant base-frame twist: an arc of a circle."""
    vx, vy, wz = twist
    x0, y0, th0 = start
    th = th0 + wz * t
    sin, cos = math.sin(th) - math.sin(th0), math.cos(th) - math.cos(th0)
    return np.array([x0 + (vx * sin + vy * cos) / wz, y0 + (-vx * cos + vy * sin) / wz, th])


@settings(max_examples=30, deadline=None)
@given(
    vx=st.floats(-0.5, 0.5),
    vy=st.floats(-0.5, 0.5),
    wz=st.floats(0.2, 1.1) | st.floats(-1.1, -0.2),
    yaw0=st.floats(-math.pi, math.pi),
)
def test_constant_twist_follows_the_analytic_circle(
    vx: float, vy: float, wz: float, yaw0: float
) -> None:
    motion = fresh((0.5, -0.3, yaw0))
    command = BaseTwist(vx=vx, vy=vy, wz=wz)
    run(motion, command, 60)  # ramp up through the acceleration limits
    np.testing.assert_allclose(motion.twist, (vx, vy, wz), atol=1e-12)
    start = motion.pose.copy()
    steps = 300  # 6 s, about one full turn at 1 rad/s
    for k in range(1, steps + 1):
        motion.step(command, DT)
        if k % 50 == 0:
            expected = analytic_pose(start, (vx, vy, wz), k * DT)
            np.testing.assert_allclose(motion.pose, expected, atol=1e-4)
    # the centre lies a quarter turn from the start velocity, |v| / |wz| away
    radius = math.hypot(vx, vy) / abs(wz)
    c, s = math.cos(start[2]), math.sin(start[2])
    v_world = np.array([c * vx - s * vy, s * vx + c * vy])
    center = start[:2] + np.array([-v_world[1], v_world[0]]) / wz
    assert np.linalg.norm(motion.pose[:2] - center) == pytest.approx(radius, abs=1e-4)


def test_pure_rotation_keeps_position() -> None:
    motion = fresh((1.0, -1.0, 0.3))
    run(motion, BaseTwist(wz=1.0), 200)
    np.testing.assert_allclose(motion.pose[:2], (1.0, -1.0), atol=1e-12)


def test_simulated_base_tracks_the_reference() -> None:
    """The physical base follows the commanded motion within the limits."""
    sim = Simulation(WorldConfig(feeder=FeederConfig(first_release_s=600.0)))
    world = sim.world
    start = world.base_pose.copy()
    speeds = []
    for _ in range(100):  # 2 s: drive away from the conveyor (the base faces it at start)
        sim.step(Command(base=BaseTwist(vx=-2.0)))
        speeds.append(float(np.linalg.norm(world.base_velocity[:2])))
    for _ in range(75):  # 1.5 s: stop
        sim.step(Command())
        speeds.append(float(np.linalg.norm(world.base_velocity[:2])))
    reference = sim.controller.base.pose
    assert np.linalg.norm(world.base_pose[:2] - reference[:2]) < 0.01
    assert max(speeds) <= CONFIG.max_linear_speed * 1.05
    assert speeds[-1] < 0.01
    travelled = world.base_pose[:2] - start[:2]
    # backwards from yaw = pi is +x in the world
    assert travelled[0] > 1.0
    assert abs(travelled[1]) < 0.01
    assert world.base_pose[2] == pytest.approx(start[2], abs=0.01)

"""The IK rate as a setting: solved less often, the arms still follow and the expert still
delivers; a rate that does not divide the control rate is refused by name."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from workcell.control.command import ArmCommand, Command
from workcell.control.simulation import Simulation
from workcell.errors import ConfigError
from workcell.expert import ExpertConfig
from workcell.session.config import SessionConfig
from workcell.session.toml_io import from_mapping
from workcell.sim.config import RobotConfig, WorldConfig
from workcell.tasks.box_transfer.episode import deliver_one_box
from workcell.tasks.box_transfer.task import BoxTransfer
from workcell.tasks.elements.expert import ExpertOperator
from workcell.teleop.rate import at_teleop_rate


def _world(ik_hz: float) -> WorldConfig:
    return WorldConfig(robot=RobotConfig(ik_hz=ik_hz))


def test_an_ik_rate_that_does_not_divide_the_control_rate_is_refused() -> None:
    with pytest.raises(ConfigError) as caught:
        RobotConfig(ik_hz=30.0)
    message = str(caught.value)
    assert "robot.ik_hz = 30" in message
    assert "must divide the control rate control_hz = 40 Hz" in message
    with pytest.raises(ConfigError, match=r"robot\.teleop_ik_hz = 30"):
        RobotConfig(teleop_ik_hz=30.0)
    # In session settings the problem is named by its full path, once.
    with pytest.raises(ConfigError) as nested:
        from_mapping(SessionConfig, {"world": {"robot": {"teleop_ik_hz": 30.0}}})
    assert [str(p).split(":")[0] for p in nested.value.problems] == [
        "world.robot.teleop_ik_hz = 30"
    ]
    assert RobotConfig(ik_hz=20.0).ik_every == 2
    assert RobotConfig().ik_every == 1  # 0: every control period


def _reach(ik_hz: float, periods: int) -> tuple[int, float, np.ndarray]:
    """The left arm follows a target 12 cm from where it starts: IK solves, the TCP's
    distance from the target at the end (m), the arm's joints."""
    sim = Simulation(_world(ik_hz), BoxTransfer().scene())
    sim.reset(0)
    for _ in range(5):
        sim.step(Command())
    start = sim.controller.ik.tcp_pose("l")
    target = start.translation() + np.array([0.08, 0.06, 0.06])
    wxyz = start.rotation().wxyz
    command = Command(
        left=ArmCommand(
            position=(float(target[0]), float(target[1]), float(target[2])),
            quaternion=(float(wxyz[0]), float(wxyz[1]), float(wxyz[2]), float(wxyz[3])),
            follow=True,
        )
    )
    solves = sim.controller.ik.solves
    for _ in range(periods):
        sim.step(command)
    reached = sim.controller.ik.tcp_pose("l").translation()
    return (
        sim.controller.ik.solves - solves,
        float(np.linalg.norm(reached - target)),
        sim.controller.ik.joints,
    )


def test_half_the_ik_rate_solves_half_as_often_and_reaches_the_same_target() -> None:
    full_solves, full_error, full_joints = _reach(0.0, 80)
    half_solves, half_error, half_joints = _reach(20.0, 80)
    assert full_solves == 80
    assert half_solves == 40
    assert full_error < 0.005 and half_error < 0.005
    assert np.abs(full_joints - half_joints).max() < 0.02


def test_the_expert_delivers_with_the_ik_at_half_the_control_rate() -> None:
    sim = Simulation(_world(20.0), BoxTransfer().scene())
    result = deliver_one_box(sim, ExpertOperator(ExpertConfig(), seed=3), 3)
    assert result.delivered


def test_a_person_drives_at_the_teleop_ik_rate() -> None:
    robot = RobotConfig(teleop_control_hz=100.0, teleop_ik_hz=50.0)
    config = SessionConfig(world=WorldConfig(robot=robot))
    driven = at_teleop_rate(config).world.robot
    assert (driven.control_hz, driven.ik_hz, driven.ik_every) == (100.0, 50.0, 2)
    unchanged = at_teleop_rate(dataclasses.replace(config, world=WorldConfig())).world.robot
    assert (unchanged.control_hz, unchanged.ik_every) == (100.0, 1)

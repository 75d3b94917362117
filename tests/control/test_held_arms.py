"""A person's session solves no IK while both arms are held (issue 38): the arms still
hold where they are, and an arm that follows again solves at once and reaches its target
as it would have."""

from __future__ import annotations

import numpy as np

from workcell.control.command import ArmCommand, BaseTwist, Command
from workcell.control.simulation import Simulation
from workcell.recording.drivers import ExpertDriver, TeleopDriver
from workcell.session.config import SessionConfig
from workcell.sim.config import RobotConfig, WorldConfig
from workcell.tasks.box_transfer.task import BoxTransfer


def _sim(solve_held_arms: bool, ik_hz: float = 0.0) -> Simulation:
    sim = Simulation(WorldConfig(robot=RobotConfig(ik_hz=ik_hz)), BoxTransfer().scene())
    sim.controller.solve_held_arms = solve_held_arms
    sim.reset(0)
    return sim


def _follow(sim: Simulation, offset: tuple[float, float, float]) -> Command:
    """The left arm follows a target ``offset`` from where its IK configuration is."""
    start = sim.controller.ik.tcp_pose("l")
    target = start.translation() + np.array(offset)
    w, x, y, z = (float(v) for v in start.rotation().wxyz)
    position = (float(target[0]), float(target[1]), float(target[2]))
    return Command(left=ArmCommand(position=position, quaternion=(w, x, y, z), follow=True))


def _drive_held(sim: Simulation, periods: int) -> list[np.ndarray]:
    """Both arms held while the base drives: the arms' joint commands, period by period."""
    moving = Command(base=BaseTwist(vx=0.3, vy=0.0, wz=0.2))
    commanded = []
    for _ in range(periods):
        sim.step(moving)
        commanded.append(sim.world.data.ctrl[sim.world.joint_ctrl].copy())
    return commanded


def test_held_arms_solve_nothing_and_stay_where_they_are() -> None:
    sim = _sim(solve_held_arms=False)
    for _ in range(40):  # the arms settle on their actuators
        sim.step(Command())
    solves = sim.controller.ik.solves
    joints = sim.controller.ik.joints
    tcp = {side: sim.world.to_base_frame(sim.world.tcp_pose(side)[0]) for side in "lr"}
    commanded = _drive_held(sim, 80)
    assert sim.controller.ik.solves == solves  # no solve while both arms are held
    assert all(np.array_equal(c, commanded[0]) for c in commanded)  # the same command
    assert np.array_equal(sim.controller.ik.joints, joints)
    for side in "lr":  # the hands hold their place on the moving base
        here = sim.world.to_base_frame(sim.world.tcp_pose(side)[0])
        assert np.linalg.norm(here - tcp[side]) < 0.005


def test_solving_for_held_arms_is_what_the_expert_does() -> None:
    sim = _sim(solve_held_arms=True)
    solves = sim.controller.ik.solves
    _drive_held(sim, 10)
    assert sim.controller.ik.solves == solves + 10


def _reach_after_holding(solve_held_arms: bool, ik_hz: float) -> tuple[int, float, np.ndarray]:
    sim = _sim(solve_held_arms, ik_hz)
    _drive_held(sim, 30)
    command = _follow(sim, (0.08, 0.06, 0.06))
    target = np.array(command.left.position)
    solves = sim.controller.ik.solves
    sim.step(command)
    first = sim.controller.ik.solves - solves  # the first period that follows solves
    for _ in range(79):
        sim.step(command)
    reached = sim.controller.ik.tcp_pose("l").translation()
    return first, float(np.linalg.norm(reached - target)), sim.controller.ik.joints


def test_an_arm_that_follows_again_solves_at_once_and_reaches_its_target() -> None:
    for ik_hz in (0.0, 20.0):  # every period, and every other one
        first, error, joints = _reach_after_holding(False, ik_hz)
        _, solved_error, solved_joints = _reach_after_holding(True, ik_hz)
        assert first == 1
        assert error < 0.005 and solved_error < 0.005
        assert np.abs(joints - solved_joints).max() < 0.05


def test_a_person_drives_without_solving_for_held_arms_and_the_expert_with() -> None:
    config = SessionConfig()
    person = Simulation(config.world, BoxTransfer().scene())
    TeleopDriver().build(config, person)
    assert not person.controller.solve_held_arms
    expert = Simulation(config.world, BoxTransfer().scene())
    ExpertDriver().build(config, expert)
    assert expert.controller.solve_held_arms

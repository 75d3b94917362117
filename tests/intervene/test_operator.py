"""The intervening operator with the real simulation, expert and teleoperation operator:
a take-over holds each arm where its IK configuration is and each gripper where the driver
left it until the person's trigger comes to it; a hand-back has the expert go on from the
hands as they are."""

from __future__ import annotations

import time

import numpy as np

from workcell.control.command import Command
from workcell.control.simulation import Simulation
from workcell.expert.phase import ExpertPhase
from workcell.intervene.operator import GRIPPER_CATCH, InterveningOperator
from workcell.protocol.messages import ControllerState, Input
from workcell.recording.drivers import ExpertDriver, InterveningDriver
from workcell.session.config import SessionConfig
from workcell.tasks.elements.expert import ExpertOperator
from workcell.tasks.registry import load_task
from workcell.teleop.operator import TeleopOperator


def _built() -> tuple[Simulation, InterveningOperator[TeleopOperator]]:
    config = SessionConfig(driver="expert")
    sim = Simulation(config.world, load_task(config.task.kind).scene())
    operator = InterveningDriver(ExpertDriver()).build(config, sim).operator
    assert isinstance(operator, InterveningOperator)
    operator.start_trial(0)
    return sim, operator


def _input(seq: int, trigger: float, grip: float = 0.0) -> Input:
    hand = ControllerState((0.0, 1.0, -0.3, 1.0, 0.0, 0.0, 0.0), grip, trigger, (0.0, 0.0), 0)
    return Input(seq, time.time(), "xr", None, hand, hand)


def test_a_take_over_holds_the_arms_and_the_grippers_until_the_trigger_comes() -> None:
    sim, operator = _built()
    for _ in range(30):  # the expert drives a moment
        sim.step(operator.act(sim.world))
    operator.last = Command(close_left=1.0, close_right=0.4)  # as if it held a box
    assert operator.take_over(sim.world) and not operator.take_over(sim.world)
    person = operator.person
    person.submit(_input(0, trigger=0.0))
    command = operator.act(sim.world)
    assert (command.close_left, command.close_right) == (1.0, 0.4)  # not dropped
    for side, arm in (("l", command.left), ("r", command.right)):
        held = operator.person.tcp_source(sim.world, side)  # the IK configuration's pose
        assert not arm.follow and np.allclose(arm.position, held[:3], atol=1e-9)
    person.submit(_input(1, trigger=0.4 + GRIPPER_CATCH / 2))  # the right trigger comes to it
    command = operator.act(sim.world)
    assert command.close_left == 1.0 and command.close_right == 0.4 + GRIPPER_CATCH / 2
    person.submit(_input(2, trigger=0.0))  # the right follows the trigger from now on
    command = operator.act(sim.world)
    assert (command.close_left, command.close_right) == (1.0, 0.0)
    assert operator.intervention() and operator.operator_input() is not None


def test_a_hand_back_has_the_expert_go_on_from_the_hands_as_they_are() -> None:
    sim, operator = _built()
    for _ in range(30):
        sim.step(operator.act(sim.world))
    operator.take_over(sim.world)
    for k in range(20):  # the person moves nothing: the arms hold
        operator.person.submit(_input(k, trigger=0.0))
        sim.step(operator.act(sim.world))
    assert operator.hand_back(sim.world) and not operator.hand_back(sim.world)
    expert = operator.driver
    assert isinstance(expert, ExpertOperator)
    assert expert.phase is ExpertPhase.BACKOFF  # no box in the hands: back off, then wait
    command = operator.act(sim.world)
    for side, arm in (("l", command.left), ("r", command.right)):
        position = sim.world.to_base_frame(sim.world.tcp_pose(side)[0])
        assert arm.follow and np.linalg.norm(np.asarray(arm.position) - position) < 0.01
    assert not operator.intervention() and operator.operator_input() is None

"""The robot-relative part of ``observation.environment_state`` (src/workcell/export/relative.py):
what each number means, checked on hand-made frames and on the real world."""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.typing import NDArray

from workcell.envs.box_transfer import BoxTransferEnv
from workcell.export.boxes import environment_names, goal_slice
from workcell.export.features import STATE_NAMES
from workcell.export.relative import goal_points, relative_features, relative_names
from workcell.tasks.box_transfer.task import BoxTransfer


def _state(
    base: tuple[float, float, float], tcp_l: tuple[float, ...], tcp_r: tuple[float, ...]
) -> NDArray[np.float64]:
    state = np.zeros((1, len(STATE_NAMES)))
    values = {"base_x": base[0], "base_y": base[1], "base_yaw": base[2]}
    for tcp, position in (("tcp_l", tcp_l), ("tcp_r", tcp_r)):
        values.update({f"{tcp}_{axis}": v for axis, v in zip("xyz", position, strict=True)})
    for name, value in values.items():
        state[0, STATE_NAMES.index(name)] = value
    return state


def test_a_box_left_of_a_base_facing_y_reads_as_ahead_and_each_hand_sees_its_offset() -> None:
    # the base at (1, 2) faces +y (yaw pi/2): a box at (1, 3) is 1 m straight ahead
    state = _state((1.0, 2.0, math.pi / 2), tcp_l=(0.9, 2.5, 0.7), tcp_r=(1.1, 2.5, 0.7))
    yaw = math.pi / 2 + 3.0  # the box turned almost a half turn from the base: -0.14 rad
    box = [1.0, 3.0, 0.8, math.cos(yaw / 2), 0.0, 0.0, math.sin(yaw / 2)]
    goal = np.array([[3.0, 2.0]])  # 2 m to the base's right
    values = relative_features(state, np.array([[box]]), goal, ("goal_x", "goal_y"))
    named = dict(zip(relative_names(1, ("goal_x", "goal_y")), values[0], strict=True))
    assert named["box0_in_base_x"] == pytest.approx(1.0)
    assert named["box0_in_base_y"] == pytest.approx(0.0, abs=1e-12)
    assert named["box0_in_base_yaw"] == pytest.approx(3.0 - math.pi)
    # the box is 0.5 m ahead of both hands, 0.1 m to the left hand's right, 0.1 m up
    assert [named[f"box0_from_tcp_l_{a}"] for a in "xyz"] == pytest.approx([0.5, -0.1, 0.1])
    assert [named[f"box0_from_tcp_r_{a}"] for a in "xyz"] == pytest.approx([0.5, 0.1, 0.1])
    assert named["goal_in_base_x"] == pytest.approx(0.0, abs=1e-12)
    assert named["goal_in_base_y"] == pytest.approx(-2.0)


def test_goal_points_are_x_y_pairs_and_other_goal_numbers_are_not() -> None:
    names = ("slot_1_x", "slot_1_y", "shelf_height", "box_0_table", "a_x", "b_y")
    assert goal_points(names) == ((0, "slot_1"),)
    assert relative_names(0, names) == ("slot_1_in_base_x", "slot_1_in_base_y")


def test_the_environment_observes_what_its_own_world_holds() -> None:
    env = BoxTransferEnv(world="D1")
    observation, _ = env.reset(seed=3)
    world = env.sim.world
    pool = env.sim.config.feeder.pool_size
    names = environment_names(pool, BoxTransfer.goal_names)
    assert len(observation["environment_state"]) == len(names)
    named = dict(zip(names, observation["environment_state"].tolist(), strict=True))
    x, y, yaw = (float(v) for v in world.base_pose)
    box = world.data.body("box_0").xpos
    ahead = math.cos(yaw) * (box[0] - x) + math.sin(yaw) * (box[1] - y)
    assert named["box0_in_base_x"] == pytest.approx(ahead, abs=1e-4)
    goal = observation["environment_state"][goal_slice(pool, BoxTransfer.goal_names)]
    to_goal = (goal[0] - x, goal[1] - y)
    left = -math.sin(yaw) * to_goal[0] + math.cos(yaw) * to_goal[1]
    assert named["goal_in_base_y"] == pytest.approx(left, abs=1e-4)
    env.close()

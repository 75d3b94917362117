"""Frames captured from the real world and formatted in bulk mean what the columns say."""

from __future__ import annotations

import json
import math

import mujoco
import numpy as np
import pytest

from workcell.control.command import ArmCommand, Command
from workcell.control.simulation import Simulation
from workcell.recording.frame_capture import (
    FrameCapture,
    OperatorInput,
    _rows_of,
    input_from_command,
)
from workcell.recording.frame_format import (
    INTEGER_COLUMNS,
    REAL_COLUMNS,
    FrameFormatter,
    build_frame,
    real_matrix,
)
from workcell.session.config import SessionConfig
from workcell.sim.joints import JOINT_ORDER
from workcell.tasks.elements.expert import ExpertOperator

VR_INPUT = OperatorInput(
    grip=(0.25, 0.75),
    trigger=(0.5, 1.0),
    controller_l=(0.1, 0.2, 0.3, 1.0, 0.0, 0.0, 0.0),
    headset=(0.0, 0.0, 1.6, 0.0, 0.0, 0.0, 1.0),
    stick_r=(0.5, -0.5),
    buttons=(3, 0),
    age_s=0.012,
    filtered_l=(0.11, 0.21, 0.31, 0.5, 0.5, 0.5, 0.5),
    filtered_headset=(0.01, 0.02, 1.59, 0.0, 0.0, 0.0, 1.0),
)


@pytest.fixture(scope="module")
def sim() -> Simulation:
    sim = Simulation(SessionConfig().world)
    sim.reset(5)
    expert = ExpertOperator()
    expert.start_trial(5)
    for _ in range(200):  # boxes on the belt, the robot on its way
        sim.step(expert.act(sim.world))
    return sim


def test_a_frame_holds_the_world_the_command_and_the_device(sim: Simulation) -> None:
    command = Command(
        left=ArmCommand((0.5, 0.2, 0.9), (0.0, 1.0, 0.0, 0.0), follow=True),
        close_right=0.75,
        head=(0.1, 0.4),
    )
    row = build_frame(
        sim.world, sim.controller, command, VR_INPUT, t_sim=1.5, t_wall=1e9, step_wall_ms=2.5
    )
    world = sim.world
    mujoco.mj_kinematics(world.model, world.data)
    for side in ("l", "r"):
        position, quaternion = world.tcp_pose(side)
        assert [row[f"tcp_{side}_{a}"] for a in "xyz"] == position.tolist()
        assert [row[f"tcp_{side}_q{a}"] for a in "wxyz"] == quaternion.tolist()
    assert [row[f"q_{j}"] for j in JOINT_ORDER] == world.joint_positions.tolist()
    assert [row[f"dq_{j}"] for j in JOINT_ORDER] == world.joint_velocities.tolist()
    assert [row["base_x"], row["base_y"], row["base_yaw"]] == world.base_pose.tolist()
    assert row["gripper_l"] == world.gripper_opening("l")
    assert (row["t_sim"], row["t_wall"], row["step_wall_ms"]) == (1.5, 1e9, 2.5)
    assert (row["target_l_x"], row["target_l_qx"], row["follow_l"]) == (0.5, 1.0, 1)
    assert (row["gripper_cmd_r"], row["head_cmd_tilt"], row["follow_r"]) == (0.75, 0.4, 0)
    assert (row["grip_l"], row["trigger_r"], row["stick_r_y"]) == (0.25, 1.0, -0.5)
    assert (row["ctrl_l_z"], row["headset_qz"], row["input_age_s"]) == (0.3, 1.0, 0.012)
    assert (row["buttons_l"], row["buttons_r"]) == (3, 0)
    filtered_l = [row[f"ctrl_l_filtered_{a}"] for a in ("x", "y", "z", "qw", "qx", "qy", "qz")]
    assert filtered_l == [0.11, 0.21, 0.31, 0.5, 0.5, 0.5, 0.5]  # beside the raw pose
    assert (row["headset_filtered_z"], row["headset_filtered_qz"]) == (1.59, 1.0)
    assert row["ctrl_r_x"] is None and row["stick_l_x"] is None  # no such device part
    assert row["ctrl_r_filtered_x"] is None
    assert row["ik_residual_l"] == sim.controller.ik.residual("l")
    boxes = json.loads(row["boxes"])
    assert [b[0] for b in boxes] == [s.index for s in world.boxes.slots]
    for entry, slot in zip(boxes, world.boxes.slots, strict=True):
        assert entry[1] == slot.state.name.lower()
        pose = np.round(world.data.qpos[slot.qpos : slot.qpos + 7], 6) + 0.0
        assert entry[2:] == pose.tolist()
    assert any(b[1] == "active" for b in boxes)


def test_an_expert_frame_has_no_device_values(sim: Simulation) -> None:
    command = Command(left=ArmCommand(follow=True), close_left=1.0)
    row = build_frame(
        sim.world,
        sim.controller,
        command,
        input_from_command(command),
        t_sim=0.0,
        t_wall=0.0,
        step_wall_ms=0.0,
    )
    assert (row["grip_l"], row["grip_r"], row["trigger_l"]) == (1.0, 0.0, 1.0)
    for name in (
        "ctrl_l_x",
        "headset_qw",
        "stick_r_x",
        "buttons_l",
        "input_age_s",
        "ctrl_l_filtered_x",
        "headset_filtered_qz",
    ):
        assert row[name] is None, name


def test_bulk_formatting_equals_one_frame_at_a_time() -> None:
    sim = Simulation(SessionConfig().world)
    sim.reset(11)
    expert = ExpertOperator()
    expert.start_trial(11)
    capture = FrameCapture(sim.world, sim.controller, capacity=40)
    singles = []
    for k in range(40 * 8):
        command = expert.act(sim.world)
        sim.step(command)
        if k % 8 == 0:
            device = VR_INPUT if k % 16 == 0 else input_from_command(command)
            t_sim = k * sim.world.control_dt
            capture.capture(command, device, t_sim=t_sim, step_wall_ms=1.0, t_wall=7.0)
            singles.append(
                build_frame(
                    sim.world,
                    sim.controller,
                    command,
                    device,
                    t_sim=t_sim,
                    t_wall=7.0,
                    step_wall_ms=1.0,
                )
            )
    assert capture.full
    frames = capture.take()
    assert len(capture) == 0 and len(frames) == 40
    batch = FrameFormatter().batch(frames, "session", "trial", 100)
    for i, single in enumerate(singles):
        real = dict(zip(REAL_COLUMNS, batch.real[i].tolist(), strict=True))
        for name, value in real.items():
            assert single[name] == (None if math.isnan(value) else value), name
        assert batch.integer[i][0] == 100 + i
        assert dict(zip(INTEGER_COLUMNS[1:], batch.integer[i][1:], strict=True)) == {
            name: single[name] for name in INTEGER_COLUMNS[1:]
        }
        assert batch.text[i] == ("session", "trial", single["boxes"], single["stage"])
    np.testing.assert_array_equal(real_matrix(frames), batch.real)
    # the box texts kept between frames are those a fresh formatter writes
    assert FrameFormatter().boxes_json(frames) == [t[2] for t in batch.text]


def test_no_device_reads_as_the_command_and_clears_an_earlier_device(sim: Simulation) -> None:
    """A frame captured without a device (None) formats exactly as one captured with
    input_from_command, even in a buffer row that held a VR device's values before."""
    command = Command(right=ArmCommand(follow=True), close_left=0.25, close_right=1.0)
    capture = FrameCapture(sim.world, sim.controller, capacity=2)
    formatter = FrameFormatter()
    capture.capture(command, VR_INPUT, t_sim=0.0, step_wall_ms=1.0, t_wall=5.0)
    capture.capture(command, input_from_command(command), t_sim=0.0, step_wall_ms=1.0, t_wall=5.0)
    with_device, explicit = formatter.batch(capture.take(), "s", "t", 0).real
    capture.capture(command, None, t_sim=0.0, step_wall_ms=1.0, t_wall=5.0)  # VR's row
    capture.capture(command, None, t_sim=0.0, step_wall_ms=1.0, t_wall=5.0)
    batch = formatter.batch(capture.take(), "s", "t", 0)
    for real in batch.real:
        np.testing.assert_array_equal(real, explicit)
    assert not np.array_equal(with_device, explicit, equal_nan=True)
    for integers in batch.integer:
        named = dict(zip(INTEGER_COLUMNS, integers, strict=True))
        assert (named["follow_l"], named["follow_r"]) == (0, 1)
        assert named["buttons_l"] is None and named["buttons_r"] is None
    real = dict(zip(REAL_COLUMNS, batch.real[0].tolist(), strict=True))
    assert (real["grip_l"], real["grip_r"], real["trigger_l"], real["trigger_r"]) == (
        0.0,
        1.0,
        0.25,
        1.0,
    )
    assert math.isnan(real["ctrl_l_x"]) and math.isnan(real["input_age_s"])


def test_site_rows_are_one_view_when_consecutive_and_views_either_way() -> None:
    array = np.arange(12.0).reshape(4, 3)
    [joined] = _rows_of(array, [1, 2])
    assert joined.tolist() == [3.0, 4.0, 5.0, 6.0, 7.0, 8.0]
    apart = _rows_of(array, [0, 2])
    assert [a.tolist() for a in apart] == [[0.0, 1.0, 2.0], [6.0, 7.0, 8.0]]
    array[2, 0] = -1.0  # views: they follow the array, as the capture needs
    assert joined[3] == -1.0 and apart[1][0] == -1.0

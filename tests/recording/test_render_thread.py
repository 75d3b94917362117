"""Cameras drawn in a thread beside the simulation: each frame shows the state it was put
in (the simulation may already have moved on), in order; a renderer that cannot be made
is said at once; a drawing error reaches the recorder at its next call."""

from __future__ import annotations

from pathlib import Path

import mujoco
import numpy as np
import pytest

from workcell.control.command import Command
from workcell.control.simulation import Simulation
from workcell.errors import RenderError
from workcell.recording.render_thread import STATE_COPIES, RenderThread
from workcell.render import OffscreenRenderer, VideoWriter
from workcell.render.video import read_frames
from workcell.sim.config import WorldConfig
from workcell.sim.joints import BASE_JOINTS

SIZE = 64
CAMERA = "wrist_l_cam"


def _turned(sim: Simulation, radians: float) -> mujoco.MjData:
    """The world's state with the base turned by ``radians`` (every camera sees it)."""
    data = mujoco.MjData(sim.world.model)
    mujoco.mj_copyData(data, sim.world.model, sim.world.data)
    model = sim.world.model
    data.qpos[model.jnt_qposadr[model.joint(BASE_JOINTS[2]).id]] += radians
    mujoco.mj_forward(sim.world.model, data)
    return data


def test_each_frame_shows_the_state_it_was_put_in(tmp_path: Path) -> None:
    sim = Simulation(WorldConfig())
    for _ in range(20):
        sim.step(Command())
    model = sim.world.model
    states = [_turned(sim, 0.4 * k) for k in range(2 * STATE_COPIES)]
    with OffscreenRenderer(model, SIZE, SIZE, quality="fast") as alone:
        expected = [alone.render(state, CAMERA) for state in states]
    thread = RenderThread(model, lambda: OffscreenRenderer(model, SIZE, SIZE, quality="fast"))
    writer = VideoWriter(tmp_path / "v.mp4", SIZE, SIZE, 20)
    live = mujoco.MjData(model)  # the simulation's data, changed right after each put
    for state in states:
        mujoco.mj_copyData(live, model, state)
        thread.put(live, [(CAMERA, writer)])
        live.qpos[:] = 0.0  # moved on at once: a thread drawing from `live` would show this
        mujoco.mj_forward(model, live)
    thread.drain()
    writer.close()
    thread.close()
    reference = VideoWriter(tmp_path / "reference.mp4", SIZE, SIZE, 20)
    for image in expected:  # the same pictures, drawn and encoded in this thread
        reference.write(image)
    reference.close()
    frames = list(read_frames(tmp_path / "v.mp4"))
    assert len(frames) == len(states)
    for i, (frame, wanted) in enumerate(
        zip(frames, read_frames(tmp_path / "reference.mp4"), strict=True)
    ):
        np.testing.assert_array_equal(frame, wanted, err_msg=f"frame {i}")


def test_a_renderer_that_cannot_be_made_is_said_at_once() -> None:
    model = Simulation(WorldConfig()).world.model
    with pytest.raises(RenderError, match="width and height must be positive"):
        RenderThread(model, lambda: OffscreenRenderer(model, 0, 0))


def test_a_drawing_error_is_raised_at_the_next_call(tmp_path: Path) -> None:
    sim = Simulation(WorldConfig())
    model = sim.world.model
    thread = RenderThread(model, lambda: OffscreenRenderer(model, SIZE, SIZE))
    writer = VideoWriter(tmp_path / "v.mp4", SIZE, SIZE, 20)
    thread.put(sim.world.data, [("no_such_cam", writer)])
    with pytest.raises(RenderError, match="unknown camera 'no_such_cam'"):
        for _ in range(10):  # raised at a later put, or at the drain
            thread.put(sim.world.data, [(CAMERA, writer)])
        thread.drain()
    thread.put(sim.world.data, [(CAMERA, writer)])  # raised once: it goes on afterwards
    thread.drain()
    writer.close()
    thread.close()
    assert len(list(read_frames(tmp_path / "v.mp4"))) >= 1

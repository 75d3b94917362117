"""Geoms out of a camera's view are left out of its drawing, and the pictures do not change:
compared pixel for pixel with every geom drawn, along a trajectory on which the base drives
and turns and the head pans and tilts (so each camera sweeps the workcell)."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from workcell.control.command import BaseTwist, Command
from workcell.control.simulation import Simulation
from workcell.render import OffscreenRenderer
from workcell.render.culling import cull_outside_view, cullable
from workcell.sim.config import WorldConfig

CAMERAS = ("head_cam", "wrist_l_cam", "wrist_r_cam")
SIZE = (96, 64)  # not square: the horizontal half angle is the wider one


def _commands() -> list[Command]:
    """Drive forward turning left, then right, a little sideways, the head looking about."""
    commands = []
    for step in range(160):
        turn = 1.0 if step < 80 else -1.0
        head = (0.8 * np.sin(step / 15.0), 0.3 + 0.4 * np.cos(step / 20.0))
        commands.append(Command(base=BaseTwist(0.6, 0.2, turn), head=head))
    return commands


@pytest.mark.parametrize("quality", ["fast", "fine"])
def test_culled_pictures_are_the_pictures_with_every_geom(quality: str) -> None:
    sim = Simulation(WorldConfig())
    model, data = sim.world.model, sim.world.data
    width, height = SIZE
    with (
        OffscreenRenderer(model, width, height, quality=quality, cull=False) as every,  # type: ignore[arg-type]
        OffscreenRenderer(model, width, height, quality=quality) as culled,  # type: ignore[arg-type]
    ):
        compared = 0
        for step, command in enumerate(_commands()):
            sim.step(command)
            if step % 8:
                continue
            for camera in CAMERAS:
                np.testing.assert_array_equal(
                    culled.render(data, camera), every.render(data, camera), err_msg=camera
                )
            strip = culled.render_all(data, CAMERAS)
            for camera in CAMERAS:
                np.testing.assert_array_equal(
                    strip[camera], every.render_all(data, CAMERAS)[camera]
                )
            compared += 1
    assert compared == 20


def test_most_geoms_are_out_of_a_wrist_camera_s_view() -> None:
    sim = Simulation(WorldConfig())
    model, data = sim.world.model, sim.world.data
    scene = mujoco.MjvScene(model, maxgeom=1000)
    camera = mujoco.MjvCamera()
    camera.type = mujoco.mjtCamera.mjCAMERA_FIXED
    camera.fixedcamid = model.camera("wrist_l_cam").id
    option = mujoco.MjvOption()
    mujoco.mjv_updateScene(model, data, option, None, camera, mujoco.mjtCatBit.mjCAT_ALL, scene)
    drawn = scene.ngeom
    assert cullable(model, camera.fixedcamid)
    culled = cull_outside_view(model, data, scene, camera.fixedcamid, 1.0)
    assert drawn // 2 < culled < drawn  # most, not all: it sees the chassis below it
    kinds = [int(scene.geoms[k].type) for k in range(scene.ngeom)]
    assert kinds.count(int(mujoco.mjtGeom.mjGEOM_NONE)) == culled
    floor = model.geom("floor").id
    assert any(  # the floor is a plane (unbounded): never culled
        scene.geoms[k].objid == floor and kinds[k] == int(mujoco.mjtGeom.mjGEOM_PLANE)
        for k in range(scene.ngeom)
    )


def test_nothing_is_left_out_when_shadows_are_on() -> None:
    """A geom out of view can cast a shadow into it: with shadows the picture is the
    picture with every geom."""
    sim = Simulation(WorldConfig())
    model, data = sim.world.model, sim.world.data
    for _ in range(40):
        sim.step(Command(base=BaseTwist(0.4, 0.0, 0.6)))
    with (
        OffscreenRenderer(model, 64, 64, shadows=True, cull=False) as every,
        OffscreenRenderer(model, 64, 64, shadows=True) as shadowed,
    ):
        for camera in CAMERAS:
            np.testing.assert_array_equal(shadowed.render(data, camera), every.render(data, camera))
        assert not shadowed._culled  # the renderer culls nothing with shadows on

"""OffscreenRenderer on the real workcell model: robot cameras, overview, errors."""

from __future__ import annotations

import os
import subprocess
import sys

import numpy as np
import pytest

from workcell.control.command import Command
from workcell.control.simulation import Simulation
from workcell.errors import RenderError
from workcell.render import OffscreenRenderer, camera_names, overview_camera
from workcell.render.quality import FAST, FAST_PLANE_GRID_M, VisualQuality
from workcell.sim.config import WorldConfig

ROBOT_CAMERAS = ("head_cam", "wrist_l_cam", "wrist_r_cam")
WIDTH, HEIGHT = 160, 120
MIN_STD = 10.0
"""A blank (single-colour) image has a pixel standard deviation near 0."""


@pytest.fixture(scope="module")
def sim() -> Simulation:
    """The default world after 1 s of idling: a box has been released onto the belt."""
    simulation = Simulation(WorldConfig())
    idle = Command()
    for _ in range(round(1.0 / simulation.control_dt)):
        simulation.step(idle)
    return simulation


@pytest.fixture(scope="module")
def renderer(sim: Simulation) -> OffscreenRenderer:
    return OffscreenRenderer(sim.world.model, WIDTH, HEIGHT)


def test_model_has_the_robot_cameras(sim: Simulation) -> None:
    assert camera_names(sim.world.model) == ROBOT_CAMERAS


@pytest.mark.parametrize("camera", ROBOT_CAMERAS)
def test_robot_camera_renders_a_non_blank_image_of_the_requested_size(
    sim: Simulation, renderer: OffscreenRenderer, camera: str
) -> None:
    image = renderer.render(sim.world.data, camera)
    assert image.shape == (HEIGHT, WIDTH, 3)
    assert image.dtype == np.uint8
    assert float(image.std()) > MIN_STD


def test_cameras_see_different_things(sim: Simulation, renderer: OffscreenRenderer) -> None:
    head = renderer.render(sim.world.data, "head_cam").astype(float)
    wrist = renderer.render(sim.world.data, "wrist_l_cam").astype(float)
    assert float(np.abs(head - wrist).mean()) > 5.0


def test_rendering_is_repeatable(sim: Simulation, renderer: OffscreenRenderer) -> None:
    first = renderer.render(sim.world.data, "head_cam")
    second = renderer.render(sim.world.data, "head_cam")
    np.testing.assert_array_equal(first, second)


def test_overview_camera_renders_with_and_without_shadows(sim: Simulation) -> None:
    model, data = sim.world.model, sim.world.data
    camera = overview_camera(model)
    with OffscreenRenderer(model, 96, 64, shadows=True) as shaded:
        with_shadows = shaded.render(data, camera)
    with OffscreenRenderer(model, 96, 64) as plain:
        without = plain.render(data, camera)
    assert with_shadows.shape == without.shape == (64, 96, 3)
    assert float(with_shadows.std()) > MIN_STD
    assert float(without.std()) > MIN_STD
    assert not np.array_equal(with_shadows, without), "the shadows flag had no effect"


def test_unknown_camera_names_the_known_cameras(
    sim: Simulation, renderer: OffscreenRenderer
) -> None:
    with pytest.raises(RenderError, match="nose_cam") as caught:
        renderer.render(sim.world.data, "nose_cam")
    for name in ROBOT_CAMERAS:
        assert name in str(caught.value)


def test_size_beyond_the_model_framebuffer_is_allowed(sim: Simulation) -> None:
    model = sim.world.model
    width = int(model.vis.global_.offwidth) + 64
    with OffscreenRenderer(model, width, 64) as wide:
        assert wide.render(sim.world.data, "head_cam").shape == (64, width, 3)


@pytest.mark.parametrize(("width", "height"), [(0, 64), (64, -1)])
def test_invalid_size_is_rejected(sim: Simulation, width: int, height: int) -> None:
    with pytest.raises(RenderError, match="positive integers"):
        OffscreenRenderer(sim.world.model, width, height)


def test_render_after_close_is_an_error(sim: Simulation) -> None:
    closed = OffscreenRenderer(sim.world.model, 64, 64)
    closed.close()
    closed.close()
    with pytest.raises(RenderError, match="after close"):
        closed.render(sim.world.data, "head_cam")


def test_missing_gl_backend_says_how_to_fix_it() -> None:
    """Without EGL (here: GLFW with no display) the error names MUJOCO_GL=egl and Mesa."""
    script = (
        "from workcell.errors import RenderError\n"
        "from workcell.render import OffscreenRenderer\n"
        "from workcell.sim.config import WorldConfig\n"
        "from workcell.sim.scene import build_world_model\n"
        "try:\n"
        "    OffscreenRenderer(build_world_model(WorldConfig()), 64, 64)\n"
        "except RenderError as error:\n"
        "    print(error)\n"
    )
    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY")}
    env["MUJOCO_GL"] = "glfw"
    done = subprocess.run(
        [sys.executable, "-c", script],
        check=False,
        capture_output=True,
        text=True,
        env=env,
        timeout=120,
    )
    assert done.returncode == 0, done.stderr
    assert "MUJOCO_GL=egl" in done.stdout
    assert "libegl1 libegl-mesa0 libgl1-mesa-dri" in done.stdout


def test_fast_quality_draws_nearly_the_same_picture_and_leaves_the_model_as_it_was(
    sim: Simulation,
) -> None:
    model = sim.world.model
    own = VisualQuality.of(model)
    assert own != FAST  # the model asks for multisampling and fine curves
    floor = model.geom("floor").id
    own_grid = float(model.geom_size[floor, 2])
    assert own_grid < FAST_PLANE_GRID_M  # the floor asks for a finer grid than fast draws
    with (
        OffscreenRenderer(model, 128, 128) as fine,
        OffscreenRenderer(model, 128, 128, quality="fast") as fast,
    ):
        assert VisualQuality.of(model) == own
        assert model.geom_size[floor, 2] == own_grid  # put back once the context is made
        for camera in ROBOT_CAMERAS:
            a = fine.render(sim.world.data, camera).astype(float)
            b = fast.render(sim.world.data, camera).astype(float)
            difference = np.abs(a - b).mean()
            assert 0.0 < difference < 8.0, (camera, difference)  # edges and plane lighting
    with pytest.raises(RenderError, match="quality 'ugly': must be one of fast, fine"):
        OffscreenRenderer(model, 32, 32, quality="ugly")  # type: ignore[arg-type]


@pytest.mark.parametrize("quality", ["fast", "fine"])
@pytest.mark.parametrize("cameras", [ROBOT_CAMERAS, ("wrist_r_cam", "head_cam")])
def test_render_all_gives_each_camera_the_picture_render_gives(
    sim: Simulation, quality: str, cameras: tuple[str, ...]
) -> None:
    with OffscreenRenderer(sim.world.model, WIDTH, HEIGHT, quality=quality) as renderer:  # type: ignore[arg-type]
        together = renderer.render_all(sim.world.data, cameras)
        assert list(together) == list(cameras)
        for camera in cameras:
            alone = renderer.render(sim.world.data, camera)
            assert together[camera].shape == (HEIGHT, WIDTH, 3)
            assert together[camera].flags.c_contiguous
            difference = np.abs(together[camera].astype(int) - alone.astype(int))
            assert int(difference.max()) <= 1, camera  # an edge pixel may round the other way
            assert float(np.mean(difference > 0)) < 1e-3, camera
        # A narrower set afterwards reuses the wide framebuffer.
        again = renderer.render_all(sim.world.data, cameras[:2])
        np.testing.assert_array_equal(again[cameras[0]], together[cameras[0]])


def test_render_all_names_an_unknown_camera(sim: Simulation, renderer: OffscreenRenderer) -> None:
    with pytest.raises(RenderError, match=r"unknown camera 'nope'.*head_cam"):
        renderer.render_all(sim.world.data, ("head_cam", "nope"))

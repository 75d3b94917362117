"""Offscreen rendering of the workcell: robot cameras and a free overview camera.

MuJoCo picks its OpenGL backend from ``MUJOCO_GL`` when ``mujoco`` is first imported, so the
variable must be set before that (the command line sets ``MUJOCO_GL=egl``); this module
never changes the environment itself.
"""

from __future__ import annotations

import mujoco
import numpy as np
from numpy.typing import NDArray

from workcell.closing import Closing
from workcell.errors import RenderError
from workcell.render.quality import RENDER_QUALITIES, RenderQuality, applied

GL_HINT = (
    "set MUJOCO_GL=egl before starting Python and install Mesa EGL "
    "(Debian/Ubuntu: apt-get install libegl1 libegl-mesa0 libgl1-mesa-dri)"
)
"""How to make offscreen rendering work on a machine without a display or GPU."""

OVERVIEW_LOOKAT = (-0.4, 0.8, 0.4)
OVERVIEW_DISTANCE = 5.3
OVERVIEW_AZIMUTH = 104.0
"""Degrees; the view direction is about +y (slightly towards -x), from the y = -4 side."""
OVERVIEW_ELEVATION = -40.0


def camera_names(model: mujoco.MjModel) -> tuple[str, ...]:
    """Names of the cameras defined in ``model``, in model order."""
    return tuple(model.camera(i).name for i in range(model.ncam))


def overview_camera(model: mujoco.MjModel) -> mujoco.MjvCamera:
    """A free camera showing the conveyor, the robot at its start and the delivery table.

    Looks across the belt from its right-hand side (y < 0): the conveyor with the feeder
    gantry on the left, the robot on the right with the delivery table behind it, storage
    racks against the far wall. The walls stand at x = -5 and y = +-5 only and there is no
    sky, so views towards +x show black beyond x = 5; this one stays clear of that and of
    the yellow pillar at (3.2, 3.2).
    """
    camera = mujoco.MjvCamera()
    mujoco.mjv_defaultFreeCamera(model, camera)
    camera.type = mujoco.mjtCamera.mjCAMERA_FREE
    camera.lookat[:] = OVERVIEW_LOOKAT
    camera.distance = OVERVIEW_DISTANCE
    camera.azimuth = OVERVIEW_AZIMUTH
    camera.elevation = OVERVIEW_ELEVATION
    return camera


class OffscreenRenderer(Closing):
    """Renders RGB images of one model at a fixed size.

    ``shadows`` turns shadows and reflections on; leave it off for per-frame cameras (it
    costs several times the render time on a software renderer) and turn it on for one-off
    pictures. ``quality`` ``fast`` halves the cost of per-frame cameras
    (:mod:`workcell.render.quality`); ``fine`` draws as the model asks. The model's
    offscreen framebuffer is enlarged when it is smaller than the requested size
    (``model.vis.global_.offwidth``/``offheight``; nothing else changes).
    Use as a context manager or call :meth:`close` to free the OpenGL context.
    """

    def __init__(
        self,
        model: mujoco.MjModel,
        width: int = 320,
        height: int = 240,
        *,
        shadows: bool = False,
        quality: RenderQuality = "fine",
    ) -> None:
        if not (isinstance(width, int) and isinstance(height, int) and width > 0 and height > 0):
            raise RenderError(
                f"image size {width!r}x{height!r}: width and height must be positive integers"
            )
        self.model = model
        self.width = width
        self.height = height
        self.shadows = shadows
        if quality not in RENDER_QUALITIES:
            raise RenderError(f"quality {quality!r}: must be one of {', '.join(RENDER_QUALITIES)}")
        self.quality = quality
        self._cameras = camera_names(model)
        visual = model.vis.global_
        visual.offwidth = max(int(visual.offwidth), width)
        visual.offheight = max(int(visual.offheight), height)
        try:
            with applied(model, quality):
                self._renderer: mujoco.Renderer | None = mujoco.Renderer(
                    model, height=height, width=width
                )
        except Exception as error:  # the GL backend raises ImportError, FatalError, ...
            raise RenderError(
                f"offscreen rendering is not available ({error}); {GL_HINT}"
            ) from error
        self.scene_option = mujoco.MjvOption()
        flags = self._renderer.scene.flags
        flags[mujoco.mjtRndFlag.mjRND_SHADOW] = shadows
        flags[mujoco.mjtRndFlag.mjRND_REFLECTION] = shadows

    @property
    def cameras(self) -> tuple[str, ...]:
        """Names of the model's cameras that :meth:`render` accepts."""
        return self._cameras

    def render(self, data: mujoco.MjData, camera: str | mujoco.MjvCamera) -> NDArray[np.uint8]:
        """An (height, width, 3) uint8 RGB image of ``data`` seen from ``camera``.

        ``camera`` is the name of a model camera (see :attr:`cameras`) or an
        :class:`mujoco.MjvCamera` such as :func:`overview_camera`.
        """
        if self._renderer is None:
            raise RenderError("render() called after close(); create a new OffscreenRenderer")
        if isinstance(camera, str) and camera not in self._cameras:
            raise RenderError(
                f"unknown camera {camera!r}; the model's cameras are: {', '.join(self._cameras)}"
            )
        self._renderer.update_scene(data, camera=camera, scene_option=self.scene_option)
        image: NDArray[np.uint8] = self._renderer.render()
        return image

    def close(self) -> None:
        """Free the OpenGL context; the renderer cannot render afterwards."""
        if self._renderer is not None:
            self._renderer.close()
            self._renderer = None

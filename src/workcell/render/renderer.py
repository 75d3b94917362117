"""Offscreen rendering of the workcell: robot cameras and a free overview camera.

MuJoCo picks its OpenGL backend from ``MUJOCO_GL`` when ``mujoco`` is first imported, so the
variable must be set before that (the command line sets ``MUJOCO_GL=egl``); this module
never changes the environment itself.
"""

from __future__ import annotations

from collections.abc import Sequence

import mujoco
import numpy as np
from numpy.typing import NDArray

from workcell.closing import Closing
from workcell.errors import RenderError
from workcell.render.culling import cull_outside_view, cullable
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
    """A free camera showing the factory's belt, the robot at its start and the table behind.

    Looks across the belt from its right-hand side (y < 0): the belt with the feeder
    gantry on the left, the robot on the right with the goal table behind it, storage
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
    (:mod:`workcell.render.quality`); ``fine`` draws as the model asks. A model camera
    draws only the geoms it can see when shadows are off (:mod:`workcell.render.culling`:
    the same pictures, for less); ``cull=False`` draws every geom. The model's
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
        cull: bool = True,
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
        # With shadows and reflections on, a geom out of view can still show in the
        # picture (its shadow, its reflection): nothing is left out then.
        self._culled = {
            name: k
            for k, name in enumerate(self._cameras)
            if cull and not shadows and cullable(model, k)
        }
        """The model cameras (name: id) that leave the geoms out of their view out."""
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
        self._set_flags(self._renderer)
        self._strip: mujoco.Renderer | None = None
        """A framebuffer as wide as several images side by side (for :meth:`render_all`),
        made on first use."""
        self._strip_cameras: list[mujoco.MjvCamera] = []

    def _set_flags(self, renderer: mujoco.Renderer) -> None:
        flags = renderer.scene.flags
        flags[mujoco.mjtRndFlag.mjRND_SHADOW] = self.shadows
        flags[mujoco.mjtRndFlag.mjRND_REFLECTION] = self.shadows

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
        if isinstance(camera, str) and camera in self._culled:
            scene, aspect = self._renderer.scene, self.width / self.height
            cull_outside_view(self.model, data, scene, self._culled[camera], aspect)
        image: NDArray[np.uint8] = self._renderer.render()
        return image

    def render_all(
        self, data: mujoco.MjData, cameras: Sequence[str]
    ) -> dict[str, NDArray[np.uint8]]:
        """One image per model camera in ``cameras``, drawn side by side into one
        framebuffer and read back once: on a software renderer one read-back (which waits
        for the drawing to finish) instead of one per camera saved about a tenth of a
        three-camera frame, before the floor grid and culling made the drawing cheaper
        (now about the same: ``bench/cameras.py``). The pictures are :meth:`render`'s, up
        to one grey level in a few edge pixels (a few in 10^5 values, where a triangle
        edge rounds the other way)."""
        if self._renderer is None:
            raise RenderError("render_all() called after close(); create a new OffscreenRenderer")
        unknown = [c for c in cameras if c not in self._cameras]
        if unknown:
            raise RenderError(
                f"unknown camera {unknown[0]!r}; the model's cameras are: "
                f"{', '.join(self._cameras)}"
            )
        if len(cameras) < 2:
            return {camera: self.render(data, camera) for camera in cameras}
        strip = self._strip_for(len(cameras))
        scene, context = strip.scene, strip._mjr_context  # mujoco.Renderer's own GL context
        width, height = self.width, self.height
        gl = strip._gl_context
        if gl is not None:
            gl.make_current()
        mujoco.mjr_setBuffer(mujoco.mjtFramebuffer.mjFB_OFFSCREEN, context)
        for k, name in enumerate(cameras):
            camera = self._strip_cameras[k]
            camera.fixedcamid = self.model.camera(name).id
            mujoco.mjv_updateScene(
                self.model, data, self.scene_option, None, camera, mujoco.mjtCatBit.mjCAT_ALL,
                scene,
            )  # fmt: skip
            if name in self._culled:
                cull_outside_view(self.model, data, scene, camera.fixedcamid, width / height)
            mujoco.mjr_render(mujoco.MjrRect(k * width, 0, width, height), scene, context)
        pixels = np.empty((height, width * len(cameras), 3), dtype=np.uint8)
        mujoco.mjr_readPixels(pixels, None, mujoco.MjrRect(0, 0, pixels.shape[1], height), context)
        image = np.flipud(pixels)
        return {
            name: np.ascontiguousarray(image[:, k * width : (k + 1) * width])
            for k, name in enumerate(cameras)
        }

    def _strip_for(self, count: int) -> mujoco.Renderer:
        """A renderer ``count`` images wide (made again when more are asked for)."""
        if self._strip is not None and len(self._strip_cameras) >= count:
            return self._strip
        if self._strip is not None:
            self._strip.close()
        visual = self.model.vis.global_
        strip_width = self.width * count
        visual.offwidth = max(int(visual.offwidth), strip_width)
        with applied(self.model, self.quality):
            self._strip = mujoco.Renderer(self.model, height=self.height, width=strip_width)
        self._set_flags(self._strip)
        self._strip_cameras = []
        for _ in range(count):
            camera = mujoco.MjvCamera()
            camera.type = mujoco.mjtCamera.mjCAMERA_FIXED
            self._strip_cameras.append(camera)
        return self._strip

    def close(self) -> None:
        """Free the OpenGL contexts; the renderer cannot render afterwards."""
        if self._strip is not None:
            self._strip.close()
            self._strip = None
        if self._renderer is not None:
            self._renderer.close()
            self._renderer = None

"""How finely the offscreen renderer draws: ``fine`` as the model asks (4x multisampling,
smooth cylinders and spheres, finely divided planes), or ``fast`` for cameras rendered at
every recorded frame (no multisampling, coarser built-in geometry: 12 slices, 6 stacks, 1
quad per plane, planes drawn as a grid no finer than 0.5 m). Both keep the skybox and turn
shadows off unless asked.

On the software renderer (Mesa llvmpipe) a three-camera 128x128 frame costs a fixed
amount per draw and per vertex, so ``fast`` renders it about six times as fast; the
pictures differ by a few grey levels at edges and in the lighting of large planes (see
``bench/cameras.py``; the coarser floor grid alone moves 0.025 % of values by at most 2
levels). MuJoCo reads these settings when a rendering context is made: :func:`applied`
sets them on the model for that moment only and puts the model's own back (a plane's grid
spacing, its third size, is for drawing only: physics never reads it)."""

from __future__ import annotations

import contextlib
from collections.abc import Iterator
from dataclasses import dataclass
from typing import Literal, get_args

import mujoco
import numpy as np

RenderQuality = Literal["fast", "fine"]
RENDER_QUALITIES: tuple[str, ...] = get_args(RenderQuality)


@dataclass(frozen=True)
class VisualQuality:
    """``model.vis.quality``'s fields that the renderer reads when its context is made."""

    offsamples: int
    numslices: int
    numstacks: int
    numquads: int

    @classmethod
    def of(cls, model: mujoco.MjModel) -> VisualQuality:
        q = model.vis.quality
        return cls(int(q.offsamples), int(q.numslices), int(q.numstacks), int(q.numquads))

    def apply(self, model: mujoco.MjModel) -> None:
        q = model.vis.quality
        q.offsamples, q.numslices = self.offsamples, self.numslices
        q.numstacks, q.numquads = self.numstacks, self.numquads


FAST = VisualQuality(offsamples=0, numslices=12, numstacks=6, numquads=1)
FAST_PLANE_GRID_M = 0.5
"""``fast``: the grid a plane is drawn as, in metres at the finest (a plane's third size;
the workcell's floor asks for 0.1 m: 25,600 squares on a 16 m floor, a quarter of a
128x128 three-camera frame's drawing time on the software renderer; 1,024 at 0.5 m)."""
CAMERA_QUALITY: RenderQuality = "fast"
"""The quality of every per-frame camera: recorded videos (unless ``collect
--camera-quality fine``), the environment's ``pixels`` and exports' re-rendered frames, so
that a policy sees in the environment what it learned from."""


@contextlib.contextmanager
def applied(model: mujoco.MjModel, quality: RenderQuality) -> Iterator[None]:
    """Inside: ``model`` asks for ``quality``; on leaving, for what it asked before."""
    own = VisualQuality.of(model)
    planes = model.geom_type == mujoco.mjtGeom.mjGEOM_PLANE
    own_grids = model.geom_size[planes, 2].copy()
    if quality == "fast":
        FAST.apply(model)
        model.geom_size[planes, 2] = np.maximum(own_grids, FAST_PLANE_GRID_M)
    try:
        yield
    finally:
        own.apply(model)
        model.geom_size[planes, 2] = own_grids

"""Geoms outside a camera's view, left out of its picture before it is drawn.

MuJoCo hands every visible geom of the scene to OpenGL whatever the camera sees. A wrist
camera looking at the chassis sees a fifth of the workcell's 169 geoms, yet on the
software renderer each one left out of view still costs its vertices' transformation and
lighting. :func:`cull_outside_view` turns the geoms whose bounding sphere lies wholly
outside a fixed camera's view volume into empty ones (``mjGEOM_NONE``), which draw
nothing. A geom outside the view volume puts no fragment on the image (with shadows and
reflections off, as for every per-frame camera: the renderer culls only then), so the
pictures are unchanged, pixel for pixel (tests/render/test_culling.py compares them along a driven
trajectory); the test is conservative (the sphere is enlarged by a margin), and planes,
which are unbounded, are always kept.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np

MARGIN_M = 0.01
"""Added to every bounding radius, besides 1 %: a geom within this of the view is kept."""

_GEOM = int(mujoco.mjtObj.mjOBJ_GEOM)
_NONE = int(mujoco.mjtGeom.mjGEOM_NONE)


def cullable(model: mujoco.MjModel, camera_id: int) -> bool:
    """Whether a model camera's view volume is the plain perspective one this module
    tests against (not orthographic, no sensor-size intrinsics)."""
    return not (
        bool(model.cam_projection[camera_id])  # orthographic
        or bool(np.any(model.cam_sensorsize[camera_id] > 0))
    )


def cull_outside_view(
    model: mujoco.MjModel,
    data: mujoco.MjData,
    scene: mujoco.MjvScene,
    camera_id: int,
    aspect: float,
) -> int:
    """Empty the geoms of ``scene`` (as :func:`mujoco.mjv_updateScene` left it for the
    fixed camera ``camera_id``, a viewport ``aspect`` = width / height) that this camera
    cannot see; returns how many."""
    count = scene.ngeom
    geoms = scene.geoms[:count]
    found = [(k, geom.objid) for k, geom in enumerate(geoms) if geom.objtype == _GEOM]
    if not found:
        return 0
    slots, objids = zip(*found, strict=True)
    ids = np.array(objids, dtype=np.int64)
    # Geom centres in the camera's frame: x right, y up, looking along -z.
    local = (data.geom_xpos[ids] - data.cam_xpos[camera_id]) @ data.cam_xmat[camera_id].reshape(
        3, 3
    )
    bound = model.geom_rbound[ids]
    radius = bound * 1.01 + MARGIN_M
    depth = -local[:, 2]
    tan_y = math.tan(math.radians(float(model.cam_fovy[camera_id])) / 2)
    tan_x = tan_y * aspect
    # Signed distance outside each side plane: |x| cos(a) - depth sin(a), a the half angle.
    outside_x = (np.abs(local[:, 0]) - depth * tan_x) / math.sqrt(1 + tan_x * tan_x)
    outside_y = (np.abs(local[:, 1]) - depth * tan_y) / math.sqrt(1 + tan_y * tan_y)
    hidden = (outside_x > radius) | (outside_y > radius) | (depth < -radius)
    hidden &= bound > 0  # a plane's radius is 0: unbounded, always kept
    culled = np.flatnonzero(hidden)
    for index in culled:
        geoms[slots[index]].type = _NONE
    return len(culled)

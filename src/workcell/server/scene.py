"""The scene description a client draws, and the poses that move it, from a MuJoCo model.

A body is dynamic when it or an ancestor has a joint (or is a mocap body); its pose is
streamed in :class:`~workcell.protocol.messages.State` in ``index`` order. Static bodies
carry their fixed world pose. Geoms keep MuJoCo's type names and ``size`` semantics.
"""

from __future__ import annotations

import base64

import mujoco
import numpy as np
from numpy.typing import NDArray

from workcell.control.simulation import Simulation
from workcell.protocol.messages import Scene
from workcell.protocol.scene import (
    BodyDescription,
    GeomDescription,
    MaterialDescription,
    Pose,
    TextureDescription,
)
from workcell.session.config import SessionConfig
from workcell.tasks.registry import load_task

HEAD_CAMERA_BODY = "head"
_SHAPES = {
    int(mujoco.mjtGeom.mjGEOM_PLANE): "plane",
    int(mujoco.mjtGeom.mjGEOM_SPHERE): "sphere",
    int(mujoco.mjtGeom.mjGEOM_CAPSULE): "capsule",
    int(mujoco.mjtGeom.mjGEOM_ELLIPSOID): "ellipsoid",
    int(mujoco.mjtGeom.mjGEOM_CYLINDER): "cylinder",
    int(mujoco.mjtGeom.mjGEOM_BOX): "box",
}
DIGITS = 5
"""Decimals kept in streamed poses (10 µm, 1e-5 of a quaternion component)."""
TEXTURE_SIDE = 64
"""Textures travel subsampled to at most this many pixels a side (a 64 x 64 RGB texture is
16 KiB of base64 in the scene message)."""
_DEFAULT_GEOM_RGBA = (0.5, 0.5, 0.5, 1.0)
"""MuJoCo's default geom colour: a geom that keeps it shows its material's colour."""


def dynamic_bodies(model: mujoco.MjModel) -> list[int]:
    """Ids of the bodies that move, in ascending order (the State pose order)."""
    moving = np.zeros(model.nbody, dtype=bool)
    for body in range(1, model.nbody):  # parents come before their children
        parent = int(model.body_parentid[body])
        own = model.body_jntnum[body] > 0 or model.body_mocapid[body] >= 0
        moving[body] = bool(own or moving[parent])
    return [int(b) for b in np.flatnonzero(moving)]


def _floats(values: NDArray[np.float64], digits: int = 6) -> tuple[float, ...]:
    return tuple(round(float(v), digits) for v in values)


def _pose(position: NDArray[np.float64], quat: NDArray[np.float64]) -> Pose:
    x, y, z = _floats(position, DIGITS)
    w, qx, qy, qz = _floats(quat, DIGITS)
    return (x, y, z, w, qx, qy, qz)


def describe(model: mujoco.MjModel, data: mujoco.MjData) -> Scene:
    """Every body with its visible primitive geoms (``data`` gives static poses)."""
    order = {body: i for i, body in enumerate(dynamic_bodies(model))}
    bodies = []
    for body in range(model.nbody):
        geoms = []
        start, count = int(model.body_geomadr[body]), int(model.body_geomnum[body])
        for geom in range(start, start + count):
            shape = _SHAPES.get(int(model.geom_type[geom]))
            rgba = _colour(model, geom)
            if shape is None or rgba[3] <= 0.0:
                continue
            sx, sy, sz = _floats(model.geom_size[geom])
            px, py, pz = _floats(model.geom_pos[geom])
            qw, qx, qy, qz = _floats(model.geom_quat[geom])
            r, g, b, a = _floats(rgba, 3)
            geoms.append(
                GeomDescription(
                    shape,
                    (sx, sy, sz),
                    (px, py, pz),
                    (qw, qx, qy, qz),
                    (r, g, b, a),
                    material=int(model.geom_matid[geom]),
                )
            )
        bodies.append(
            BodyDescription(
                name=model.body(body).name or f"body_{body}",
                index=order.get(body, -1),
                dynamic=body in order,
                pose=_pose(data.xpos[body], data.xquat[body]),
                geoms=tuple(geoms),
            )
        )
    materials = tuple(_material(model, i) for i in range(model.nmat))
    return Scene(bodies=tuple(bodies), head_camera_body=HEAD_CAMERA_BODY, materials=materials)


def _colour(model: mujoco.MjModel, geom: int) -> NDArray[np.float64]:
    """The colour MuJoCo draws a geom in: its own, or its material's when it kept the
    default."""
    rgba: NDArray[np.float64] = model.geom_rgba[geom]
    material = int(model.geom_matid[geom])
    if material >= 0 and tuple(float(v) for v in rgba) == _DEFAULT_GEOM_RGBA:
        mat_rgba: NDArray[np.float64] = model.mat_rgba[material]
        return mat_rgba
    return rgba


def _material(model: mujoco.MjModel, material: int) -> MaterialDescription:
    texture = int(model.mat_texid[material, int(mujoco.mjtTextureRole.mjTEXROLE_RGB)])
    return MaterialDescription(
        name=model.material(material).name,
        specular=round(float(model.mat_specular[material]), 3),
        shininess=round(float(model.mat_shininess[material]), 3),
        emission=round(float(model.mat_emission[material]), 3),
        texture=_texture(model, texture, model.mat_texrepeat[material]) if texture >= 0 else None,
    )


def _texture(
    model: mujoco.MjModel, texture: int, repeat: NDArray[np.float64]
) -> TextureDescription | None:
    """A 2D texture's RGB pixels, every k-th row and column (k keeps both sides <= 64)."""
    if int(model.tex_type[texture]) != int(mujoco.mjtTexture.mjTEXTURE_2D):
        return None
    width, height = int(model.tex_width[texture]), int(model.tex_height[texture])
    channels, start = int(model.tex_nchannel[texture]), int(model.tex_adr[texture])
    pixels = model.tex_data[start : start + width * height * channels].reshape(
        height, width, channels
    )
    stride = max(1, -(-max(width, height) // TEXTURE_SIDE))
    kept = pixels[::stride, ::stride]
    # A grey texture repeats its one channel.
    rgb = np.ascontiguousarray(kept[..., :3] if channels >= 3 else np.repeat(kept, 3, axis=2))
    return TextureDescription(
        width=int(rgb.shape[1]),
        height=int(rgb.shape[0]),
        rgb=base64.b64encode(rgb.tobytes()).decode("ascii"),
        repeat=(round(float(repeat[0]), 3), round(float(repeat[1]), 3)),
    )


class PoseReader:
    """Reads the dynamic bodies' world poses from ``data`` (after forward kinematics)."""

    def __init__(self, model: mujoco.MjModel) -> None:
        self.bodies = np.array(dynamic_bodies(model), dtype=int)

    def poses(self, data: mujoco.MjData) -> tuple[Pose, ...]:
        stacked = np.round(
            np.concatenate([data.xpos[self.bodies], data.xquat[self.bodies]], axis=1), DIGITS
        )
        return tuple((x, y, z, w, qx, qy, qz) for x, y, z, w, qx, qy, qz in stacked.tolist())


def idle_scene(config: SessionConfig) -> Scene:
    """The scene of a freshly reset world with ``config`` (what an idle client draws)."""
    world = Simulation(config.world, load_task(config.task.kind).scene()).world
    return describe(world.model, world.data)

"""The scene a browser draws carries the model's own materials and textures."""

from __future__ import annotations

import base64

import mujoco
import numpy as np

from workcell.protocol.messages import Scene
from workcell.server.scene import TEXTURE_SIDE, describe
from workcell.sim.config import WorldConfig
from workcell.sim.looks import LOOKS
from workcell.sim.scene import build_world_model


def _scene() -> tuple[mujoco.MjModel, Scene]:
    model = build_world_model(WorldConfig())
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    return model, describe(model, data)


def test_every_material_is_described_with_its_shading() -> None:
    model, scene = _scene()
    materials = scene.materials
    assert [m.name for m in materials] == [model.material(i).name for i in range(model.nmat)]
    for material in materials:
        look = LOOKS.get(material.name)
        if look is not None:
            assert (material.specular, material.shininess, material.emission) == (
                look.specular,
                look.shininess,
                look.emission,
            )


def test_geoms_point_at_their_material() -> None:
    _, scene = _scene()
    by_name = {b.name: b for b in scene.bodies}
    names = [m.name for m in scene.materials]
    chassis = by_name["base"].geoms[0]
    assert names[chassis.material] == "robot_shell"
    belt = by_name["conveyor"].geoms[0]
    assert names[belt.material] == "rubber"
    for body in scene.bodies:
        for geom in body.geoms:
            assert -1 <= geom.material < len(names)


def test_the_floor_texture_travels_as_the_models_pixels() -> None:
    model, scene = _scene()
    floor = next(m for m in scene.materials if m.name == "floor_mat")
    texture = floor.texture
    assert texture is not None
    assert max(texture.width, texture.height) <= TEXTURE_SIDE
    assert texture.repeat == tuple(
        float(v) for v in model.mat_texrepeat[model.material("floor_mat").id]
    )
    pixels = np.frombuffer(base64.b64decode(texture.rgb), dtype=np.uint8)
    assert pixels.size == texture.width * texture.height * 3
    tex = int(
        model.mat_texid[model.material("floor_mat").id, int(mujoco.mjtTextureRole.mjTEXROLE_RGB)]
    )
    width, height = int(model.tex_width[tex]), int(model.tex_height[tex])
    full = model.tex_data[model.tex_adr[tex] : model.tex_adr[tex] + width * height * 3]
    stride = width // texture.width
    expected = full.reshape(height, width, 3)[::stride, ::stride]
    np.testing.assert_array_equal(pixels.reshape(texture.height, texture.width, 3), expected)
    # The slab joints (the texture's edge mark) survive the subsampling: a darker first row.
    image = expected.astype(float)
    assert image[0].mean() < image[1:].mean() - 20

"""How the workcell looks: named MuJoCo materials, and scenery that weighs nothing.

Every geom keeps its own colour (``rgba``); its material says how light plays on it, so
camera renders and the browser (which draws the model's own materials, see
:mod:`workcell.server.scene`) shade it alike: glossy robot shells, painted steel, matte
rubber and cardboard, a lit status strip. Decor (floor markings, joint collars, the status
strip) is geoms named ``decor_*`` with no mass and no contacts: it changes what the model
looks like and nothing of how it moves.
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco

from workcell.sim.spec_utils import set_visual_only

DECOR_PREFIX = "decor_"
"""Name prefix of every massless, contact-free decor geom."""


@dataclass(frozen=True)
class Look:
    """MuJoCo material shading, each 0-1: highlight strength, highlight tightness, glow."""

    specular: float
    shininess: float
    emission: float = 0.0


LOOKS: dict[str, Look] = {
    "robot_shell": Look(specular=0.6, shininess=0.7),
    "painted_steel": Look(specular=0.35, shininess=0.45),
    "floor_paint": Look(specular=0.08, shininess=0.2),
    "rubber": Look(specular=0.05, shininess=0.1),
    "cardboard": Look(specular=0.04, shininess=0.05),
    "plaster": Look(specular=0.02, shininess=0.05),
    "signal": Look(specular=0.3, shininess=0.5, emission=0.8),
}


def add_looks(spec: mujoco.MjSpec, *names: str) -> None:
    """Add the named looks as materials of ``spec`` (those it does not have yet)."""
    for name in names:
        if spec.material(name) is not None:
            continue
        look = LOOKS[name]
        spec.add_material(
            name=name, specular=look.specular, shininess=look.shininess, emission=look.emission
        )


def add_decor(
    body: mujoco.MjsBody,
    name: str,
    geom_type: mujoco.mjtGeom,
    size: list[float],
    *,
    rgba: tuple[float, float, float, float],
    material: str,
    pos: list[float] | None = None,
    quat: list[float] | None = None,
) -> mujoco.MjsGeom:
    """A geom to look at: no mass (the body's inertia is unchanged) and no contacts."""
    geom = body.add_geom(
        name=DECOR_PREFIX + name,
        type=geom_type,
        size=size,
        pos=pos or [0.0, 0.0, 0.0],
        quat=quat or [1.0, 0.0, 0.0, 0.0],
        rgba=list(rgba),
        mass=0.0,
        material=material,
    )
    set_visual_only(geom)
    return geom

"""What a client draws, described: every body of the compiled MuJoCo model, its shapes and
their shading; the parts of the :class:`~workcell.protocol.messages.Scene` message, sent on
connect and when a session starts. The server builds them in :mod:`workcell.server.scene`.
"""

from __future__ import annotations

from dataclasses import dataclass

Pose = tuple[float, float, float, float, float, float, float]
"""(x, y, z, qw, qx, qy, qz): metres and a unit quaternion."""


@dataclass(frozen=True)
class GeomDescription:
    """A primitive shape: MuJoCo geom type name (``box``, ``sphere``, ``capsule``,
    ``cylinder``, ``plane``, ``ellipsoid``), MuJoCo ``size`` semantics, pose relative to
    its body, colour."""

    shape: str
    size: tuple[float, float, float]
    pos: tuple[float, float, float]
    quat: tuple[float, float, float, float]
    rgba: tuple[float, float, float, float]
    material: int = -1
    """Index into :attr:`~workcell.protocol.messages.Scene.materials` of the geom's
    shading, or -1 for none (matte)."""


@dataclass(frozen=True)
class BodyDescription:
    """A body of the compiled model; ``index`` is its position in :class:`State` poses
    when ``dynamic`` (it moves), else its fixed world pose is ``pose``."""

    name: str
    index: int
    dynamic: bool
    pose: Pose
    geoms: tuple[GeomDescription, ...]


@dataclass(frozen=True)
class TextureDescription:
    """A model's 2D texture, as pixels: ``width`` x ``height`` RGB bytes (row by row, the
    model's own rows subsampled to at most 64 a side), base64; ``repeat`` is how often it
    repeats across the geom's two sides (MuJoCo ``texrepeat``)."""

    width: int
    height: int
    rgb: str
    repeat: tuple[float, float]


@dataclass(frozen=True)
class MaterialDescription:
    """A MuJoCo material's shading (``specular``, ``shininess``, ``emission``: 0-1, as
    MuJoCo's renderer uses them) and its texture, if any. The geom's ``rgba`` is its colour."""

    name: str
    specular: float
    shininess: float
    emission: float
    texture: TextureDescription | None

"""Quaternions (w, x, y, z) and the fixed turn from the WebXR frame to the robot base frame.

WebXR ``local-floor``: x right, y up, -z forward. Base frame: x forward, y left, z up. So
base x = -xr z, base y = -xr x, base z = xr y: the rotation matrix

    M = [[0, 0, -1],
         [-1, 0, 0],
         [0, 1, 0]]

whose quaternion is (0.5, 0.5, -0.5, -0.5). A displacement d maps to M d; a rotation R
seen in the XR frame is M R Mᵀ in the base frame.
"""

from __future__ import annotations

import math

Vec3 = tuple[float, float, float]
Quat = tuple[float, float, float, float]

XR_TO_BASE: Quat = (0.5, 0.5, -0.5, -0.5)
"""The rotation M taking XR-frame vectors to base-frame vectors."""
IDENTITY: Quat = (1.0, 0.0, 0.0, 0.0)


def multiply(a: Quat, b: Quat) -> Quat:
    """The Hamilton product a ⊗ b (apply b, then a)."""
    aw, ax, ay, az = a
    bw, bx, by, bz = b
    return (
        aw * bw - ax * bx - ay * by - az * bz,
        aw * bx + ax * bw + ay * bz - az * by,
        aw * by - ax * bz + ay * bw + az * bx,
        aw * bz + ax * by - ay * bx + az * bw,
    )


def conjugate(q: Quat) -> Quat:
    return (q[0], -q[1], -q[2], -q[3])


def normalize(q: Quat) -> Quat:
    norm = math.sqrt(sum(c * c for c in q))
    if norm == 0.0 or not math.isfinite(norm):
        return IDENTITY
    w, x, y, z = (c / norm for c in q)
    return (w, x, y, z) if w >= 0.0 else (-w, -x, -y, -z)


def rotate(q: Quat, v: Vec3) -> Vec3:
    """Vector ``v`` rotated by unit quaternion ``q``."""
    _, x, y, z = multiply(multiply(q, (0.0, *v)), conjugate(q))
    return (x, y, z)


def xr_to_base_vector(v: Vec3) -> Vec3:
    """An XR-frame displacement in the base frame."""
    return (-v[2], -v[0], v[1])


def xr_to_base_rotation(q: Quat) -> Quat:
    """A rotation expressed in the XR frame, expressed in the base frame (M R Mᵀ)."""
    return normalize(multiply(multiply(XR_TO_BASE, q), conjugate(XR_TO_BASE)))

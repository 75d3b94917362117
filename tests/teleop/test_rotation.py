"""The XR → base frame turn, checked against the mapping written out by hand."""

from __future__ import annotations

import math

import pytest

from workcell.teleop.rotation import (
    XR_TO_BASE,
    multiply,
    normalize,
    rotate,
    xr_to_base_rotation,
    xr_to_base_vector,
)


def close(a: tuple[float, ...], b: tuple[float, ...], tol: float = 1e-12) -> bool:
    return all(math.isclose(x, y, abs_tol=tol) for x, y in zip(a, b, strict=True))


@pytest.mark.parametrize(
    ("xr", "base"),
    [
        ((0.0, 0.0, -1.0), (1.0, 0.0, 0.0)),  # XR forward (-z) is base forward (+x)
        ((-1.0, 0.0, 0.0), (0.0, 1.0, 0.0)),  # XR left (-x) is base left (+y)
        ((0.0, 1.0, 0.0), (0.0, 0.0, 1.0)),  # XR up (+y) is base up (+z)
        ((0.3, -0.2, 0.5), (-0.5, -0.3, -0.2)),
    ],
)
def test_vectors(xr: tuple[float, float, float], base: tuple[float, float, float]) -> None:
    assert xr_to_base_vector(xr) == base
    assert close(rotate(XR_TO_BASE, xr), base)  # the quaternion is the same turn


def test_quaternion_helpers() -> None:
    quarter_z = (math.cos(math.pi / 4), 0.0, 0.0, math.sin(math.pi / 4))
    assert close(rotate(quarter_z, (1.0, 0.0, 0.0)), (0.0, 1.0, 0.0))
    assert close(multiply(quarter_z, quarter_z), (0.0, 0.0, 0.0, 1.0))
    assert normalize((-2.0, 0.0, 0.0, 0.0)) == (1.0, 0.0, 0.0, 0.0)
    assert normalize((0.0, 0.0, 0.0, 0.0)) == (1.0, 0.0, 0.0, 0.0)


def test_rotations_about_xr_axes_become_rotations_about_base_axes() -> None:
    angle = 0.7
    c, s = math.cos(angle / 2), math.sin(angle / 2)
    # turning about XR up (+y) is turning about base up (+z): a yaw to the left
    assert close(xr_to_base_rotation((c, 0.0, s, 0.0)), (c, 0.0, 0.0, s))
    # about XR +x (right) is about base -y; about XR +z (backward) is about base -x
    assert close(xr_to_base_rotation((c, s, 0.0, 0.0)), (c, 0.0, -s, 0.0))
    assert close(xr_to_base_rotation((c, 0.0, 0.0, s)), (c, -s, 0.0, 0.0))

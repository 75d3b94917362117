"""Arm kinematics from the Franka Emika Panda's published parameters.

Source: Franka Control Interface documentation, "Robot and interface specifications":
modified (Craig) Denavit-Hartenberg parameters, joint position limits and joint velocity
limits of the Panda arm. Masses are the rounded link masses of the published dynamic model.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class DHLink:
    """One joint in modified DH convention: a_{i-1}, d_i, alpha_{i-1}."""

    a: float
    d: float
    alpha: float


HALF_PI = 1.5707963267948966

DH: tuple[DHLink, ...] = (
    DHLink(a=0.0, d=0.333, alpha=0.0),
    DHLink(a=0.0, d=0.0, alpha=-HALF_PI),
    DHLink(a=0.0, d=0.316, alpha=HALF_PI),
    DHLink(a=0.0825, d=0.0, alpha=HALF_PI),
    DHLink(a=-0.0825, d=0.384, alpha=-HALF_PI),
    DHLink(a=0.0, d=0.0, alpha=HALF_PI),
    DHLink(a=0.088, d=0.0, alpha=HALF_PI),
)
FLANGE_D = 0.107

JOINT_LIMITS: tuple[tuple[float, float], ...] = (
    (-2.8973, 2.8973),
    (-1.7628, 1.7628),
    (-2.8973, 2.8973),
    (-3.0718, -0.0698),
    (-2.8973, 2.8973),
    (-0.0175, 3.7525),
    (-2.8973, 2.8973),
)
VELOCITY_LIMITS: tuple[float, ...] = (2.175, 2.175, 2.175, 2.175, 2.61, 2.61, 2.61)
LINK_MASSES: tuple[float, ...] = (4.97, 0.65, 3.23, 3.59, 1.23, 1.67, 0.74)

POSITION_GAINS: tuple[float, ...] = (4500.0, 4500.0, 3500.0, 3500.0, 2000.0, 2000.0, 2000.0)
DAMPING_GAINS: tuple[float, ...] = (450.0, 450.0, 350.0, 350.0, 200.0, 200.0, 200.0)

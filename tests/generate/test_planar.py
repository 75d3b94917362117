"""Planar motions: composition, inverse, and moving points and orientations alike."""

from __future__ import annotations

import math

import numpy as np

from workcell.generate.planar import Planar, yaw_of


def test_between_carries_the_source_pose_onto_the_target() -> None:
    source, target = Planar(0.3, -0.2, 0.4), Planar(-1.0, 0.5, -0.9)
    motion = Planar.between(source, target)
    moved = motion.compose(source)
    assert np.allclose((moved.x, moved.y, moved.yaw), (target.x, target.y, target.yaw))
    identity = motion.compose(motion.inverse())
    assert np.allclose((identity.x, identity.y, identity.yaw), (0, 0, 0), atol=1e-12)


def test_points_and_orientations_move_as_one_rigid_body() -> None:
    motion = Planar(0.5, -0.25, math.pi / 2)
    points = np.array([[1.0, 0.0, 0.7], [0.0, 2.0, 0.1]])
    assert np.allclose(motion.points(points), [[0.5, 0.75, 0.7], [-1.5, -0.25, 0.1]])
    quats = np.array([[math.cos(0.1), 0.0, 0.0, math.sin(0.1)]])  # yaw 0.2
    turned = motion.quaternions(quats)
    assert math.isclose(yaw_of(turned[0]), 0.2 + math.pi / 2)
    assert math.isclose(float(np.linalg.norm(turned[0])), 1.0)
    poses = np.array([[1.0, 0.0, 0.2]])
    assert np.allclose(motion.poses(poses), [[0.5, 0.75, 0.2 + math.pi / 2]])

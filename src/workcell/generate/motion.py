"""Sampling a source trial's motion at any instant, in the world, moved by a segment's motion.

End-effector targets are recorded in the base frame; in the world they are the recorded
base pose times the target. A segment moves the base's path and both targets alike
(:class:`~workcell.generate.planar.Planar`), and the targets go back into the frame of the
base as it actually stands when commanded, so the arms make up for the base's tracking
error.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from workcell.generate.planar import Planar, wrap
from workcell.generate.source import SourceTrial


@dataclass(frozen=True)
class MotionSample:
    """The source's motion at one instant, in the attempt's world."""

    base: NDArray[np.float64]
    """(3,): x, y, yaw the base should be at."""
    twist: NDArray[np.float64]
    """(3,): the source's commanded twist (base frame) there."""
    hands: NDArray[np.float64]
    """(2, 7): both TCP targets in the world (x, y, z, qw, qx, qy, qz)."""
    follow: tuple[bool, bool]
    close: tuple[float, float]
    head: tuple[float, float]


def hands_in_world(base: NDArray[np.float64], targets: NDArray[np.float64]) -> NDArray[np.float64]:
    """Base-frame TCP targets (2, 7) of a base at ``base`` (x, y, yaw), in the world."""
    frame = Planar.of(base)
    out = np.empty_like(targets)
    out[:, :3] = frame.points(targets[:, :3])
    out[:, 3:] = frame.quaternions(targets[:, 3:])
    return out


def hands_in_base(base: NDArray[np.float64], hands: NDArray[np.float64]) -> NDArray[np.float64]:
    """World TCP targets (2, 7) in the frame of a base at ``base``."""
    return hands_in_world(_inverse(base), hands)


def _inverse(base: NDArray[np.float64]) -> NDArray[np.float64]:
    inv = Planar.of(base).inverse()
    return np.array([inv.x, inv.y, inv.yaw])


def sample(source: SourceTrial, t: float, motion: Planar) -> MotionSample:
    """``source`` at its trial time ``t`` (interpolated between frames; discrete commands
    held from the frame before), moved by ``motion``."""
    times = source.t
    k = int(np.clip(np.searchsorted(times, t, side="right") - 1, 0, len(times) - 1))
    j = min(k + 1, len(times) - 1)
    span = times[j] - times[k]
    a = 0.0 if span <= 0 else float(np.clip((t - times[k]) / span, 0.0, 1.0))
    base_k, base_j = source.base[k], source.base[j]
    base = base_k + a * (base_j - base_k)
    base[2] = base_k[2] + a * wrap(float(base_j[2] - base_k[2]))
    hands_k = hands_in_world(base_k, source.targets[k])
    hands_j = hands_in_world(base_j, source.targets[j])
    hands = blend(hands_k, hands_j, a)
    moved = motion.poses(base[None, :])[0]
    moved_hands = np.empty_like(hands)
    moved_hands[:, :3] = motion.points(hands[:, :3])
    moved_hands[:, 3:] = motion.quaternions(hands[:, 3:])
    return MotionSample(
        base=moved,
        twist=source.twist[k].copy(),
        hands=moved_hands,
        follow=(bool(source.follow[k, 0]), bool(source.follow[k, 1])),
        close=(float(source.close[k, 0]), float(source.close[k, 1])),
        head=(float(source.head[k, 0]), float(source.head[k, 1])),
    )


def smoothstep(s: float) -> float:
    """``s`` in [0, 1] eased in and out: 3 s^2 - 2 s^3 (zero slope at both ends)."""
    return s * s * (3 - 2 * s)


def smoothstep_rate(s: float) -> float:
    """:func:`smoothstep`'s slope at ``s``: 6 s (1 - s)."""
    return 6 * s * (1 - s)


def blend(a: NDArray[np.float64], b: NDArray[np.float64], s: float) -> NDArray[np.float64]:
    """Poses (m, 7) a fraction ``s`` of the way from ``a`` to ``b`` (positions linear,
    orientations normalized linear on the shorter arc)."""
    out = np.empty_like(a)
    out[:, :3] = a[:, :3] + s * (b[:, :3] - a[:, :3])
    qa, qb = a[:, 3:], b[:, 3:].copy()
    flip = np.sum(qa * qb, axis=1) < 0
    qb[flip] *= -1
    q = qa + s * (qb - qa)
    out[:, 3:] = q / np.linalg.norm(q, axis=1, keepdims=True)
    return out


def widen(hands: NDArray[np.float64], half: float, lift: float) -> NDArray[np.float64]:
    """Both hands moved apart by ``half`` each (along the line between them, on the floor
    plane) and up by ``lift``: a grasp re-aimed at a box wider by ``2 * half`` and taller
    by ``2 * lift``."""
    if half == 0.0 and lift == 0.0:
        return hands
    out = hands.copy()
    apart = hands[0, :2] - hands[1, :2]
    norm = math.hypot(float(apart[0]), float(apart[1]))
    if norm > 1e-6:
        unit = apart / norm
        out[0, :2] += half * unit
        out[1, :2] -= half * unit
    out[:, 2] += lift
    return out

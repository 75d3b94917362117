"""The One-Euro filter (Casiez, Roussel and Vogel, CHI 2012) for tracked poses.

A first-order low-pass filter whose cutoff frequency rises with the signal's speed:
``cutoff = min_cutoff + beta * speed``, the speed itself low-passed at ``d_cutoff``. A
pose held still is smoothed strongly (jitter goes), a fast motion passes with little lag.
A pose is filtered as a position (speed in m/s) and a unit quaternion (kept in the
previous estimate's hemisphere, renormalised; its speed is the angular speed in rad/s).
Samples are timed by the caller's clock; a sample with no time elapsed is ignored.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

Vector = tuple[float, ...]
Pose = tuple[float, float, float, float, float, float, float]
"""x, y, z, qw, qx, qy, qz."""


def smoothing(dt: float, cutoff_hz: float) -> float:
    """The exponential smoothing factor of a low-pass at ``cutoff_hz`` for a step ``dt``."""
    tau = 1.0 / (2.0 * math.pi * cutoff_hz)
    return 1.0 / (1.0 + tau / dt)


@dataclass(frozen=True)
class OneEuroParameters:
    min_cutoff_hz: float
    beta: float
    d_cutoff_hz: float


class OneEuro:
    """One-Euro filter of a vector; ``speed_scale`` turns the vector's rate of change into
    the speed the cutoff rises with (2 for a unit quaternion: its angular speed)."""

    def __init__(self, parameters: OneEuroParameters, speed_scale: float = 1.0) -> None:
        self.parameters = parameters
        self.speed_scale = speed_scale
        self._t: float | None = None
        self._x: Vector = ()
        self._dx: Vector = ()

    def reset(self) -> None:
        self._t = None

    @property
    def value(self) -> Vector:
        return self._x

    def __call__(self, t: float, x: Sequence[float]) -> Vector:
        sample = tuple(float(v) for v in x)
        if self._t is None or len(sample) != len(self._x):
            self._t, self._x, self._dx = t, sample, (0.0,) * len(sample)
            return sample
        dt = t - self._t
        if dt <= 0.0:
            return self._x
        p = self.parameters
        rate = tuple((v - w) / dt for v, w in zip(sample, self._x, strict=True))
        a_d = smoothing(dt, p.d_cutoff_hz)
        self._dx = tuple(a_d * r + (1.0 - a_d) * d for r, d in zip(rate, self._dx, strict=True))
        speed = self.speed_scale * math.sqrt(sum(d * d for d in self._dx))
        a = smoothing(dt, p.min_cutoff_hz + p.beta * speed)
        self._x = tuple(a * v + (1.0 - a) * w for v, w in zip(sample, self._x, strict=True))
        self._t = t
        return self._x


class PoseFilter:
    """One-Euro filters of one tracked pose's position and orientation."""

    def __init__(
        self, min_cutoff_hz: float, beta_position: float, beta_rotation: float, d_cutoff_hz: float
    ) -> None:
        self.position = OneEuro(OneEuroParameters(min_cutoff_hz, beta_position, d_cutoff_hz))
        self.rotation = OneEuro(
            OneEuroParameters(min_cutoff_hz, beta_rotation, d_cutoff_hz), speed_scale=2.0
        )

    def reset(self) -> None:
        """Tracking was lost (or the link dropped): the next pose starts afresh."""
        self.position.reset()
        self.rotation.reset()

    def __call__(self, t: float, pose: Pose) -> Pose:
        quat: Vector = pose[3:]
        previous = self.rotation.value
        if len(previous) == 4 and sum(a * b for a, b in zip(quat, previous, strict=True)) < 0:
            quat = tuple(-q for q in quat)  # the same rotation, in the estimate's hemisphere
        x, y, z = self.position(t, pose[:3])
        w, qx, qy, qz = self.rotation(t, quat)
        norm = math.sqrt(w * w + qx * qx + qy * qy + qz * qz) or 1.0
        return (x, y, z, w / norm, qx / norm, qy / norm, qz / norm)

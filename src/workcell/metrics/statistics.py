"""Session-level statistics: Wilson success-rate interval and descriptive summaries.

The paper reports success rate with a Wilson 95 % interval and trial metrics as
mean +- sample SD and median [IQR] (paper sections IV-D, V). Values keep their units.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from workcell.errors import MetricsError

Z_95 = 1.959963984540054
"""Two-sided 95 % standard normal quantile."""


def _is_count(value: object) -> bool:
    return isinstance(value, int | np.integer) and not isinstance(value, bool)


def wilson_interval(
    successes: int | np.integer[Any], n: int | np.integer[Any], z: float = Z_95
) -> tuple[float, float]:
    """Wilson score interval (low, high) of a success proportion, both in [0, 1].

    ``successes`` of ``n`` attempts; ``z`` the normal quantile (default: 95 %). (nan, nan)
    for n = 0. Raises :class:`MetricsError` unless 0 <= successes <= n are integers and z
    is a finite number > 0.
    """
    if not (_is_count(successes) and _is_count(n) and 0 <= successes <= n):
        raise MetricsError(
            f"successes = {successes!r}, n = {n!r}: need integers with 0 <= successes <= n"
        )
    if not (isinstance(z, int | float) and math.isfinite(z) and z > 0):
        raise MetricsError(f"z = {z!r}: must be a finite number > 0")
    if n == 0:
        return (math.nan, math.nan)
    p = successes / n
    z2 = z * z
    denominator = 1.0 + z2 / n
    centre = (p + z2 / (2 * n)) / denominator
    half = z / denominator * math.sqrt(p * (1.0 - p) / n + z2 / (4 * n * n))
    low = 0.0 if successes == 0 else max(0.0, centre - half)
    high = 1.0 if successes == n else min(1.0, centre + half)
    return (low, high)


@dataclass(frozen=True)
class Descriptive:
    """Summary of the finite values of one metric, in that metric's unit.

    ``n`` counts the finite values; ``sd`` is the sample SD (ddof = 1, NaN for n < 2);
    ``q1``, ``median``, ``q3`` use numpy's default linear quantiles. Every float is NaN
    for n = 0.
    """

    n: int
    mean: float
    sd: float
    median: float
    q1: float
    q3: float
    minimum: float
    maximum: float


def describe(values: npt.NDArray[Any] | Sequence[float]) -> Descriptive:
    """Descriptive statistics of ``values``; NaN and infinite values are dropped first."""
    data = np.asarray(values, dtype=np.float64).ravel()
    data = data[np.isfinite(data)]
    n = int(data.size)
    if n == 0:
        nan = math.nan
        return Descriptive(0, nan, nan, nan, nan, nan, nan, nan)
    q1, median, q3 = (float(v) for v in np.quantile(data, (0.25, 0.5, 0.75)))
    return Descriptive(
        n=n,
        mean=float(data.mean()),
        sd=float(data.std(ddof=1)) if n >= 2 else math.nan,
        median=median,
        q1=q1,
        q3=q3,
        minimum=float(data.min()),
        maximum=float(data.max()),
    )

"""Wilson interval and descriptive statistics against hand-worked values."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest

from workcell.metrics import Descriptive, MetricsError, describe, wilson_interval


def test_wilson_reproduces_the_paper() -> None:
    # paper section V-A: 37 of 53 trials, Wilson 95 % CI 56.46-80.48 %
    low, high = wilson_interval(37, 53)
    assert (round(low, 4), round(high, 4)) == (0.5646, 0.8048)


def test_wilson_by_hand_with_z_two() -> None:
    # p = 0.5, z^2 = 4, n = 10: denominator 1 + 4/10 = 1.4; centre (0.5 + 0.2) / 1.4 = 0.5
    # half width 2 / 1.4 * sqrt(0.25/10 + 4/400) = 1.4285714 * sqrt(0.035) = 0.2672612
    low, high = wilson_interval(5, 10, z=2.0)
    assert low == pytest.approx(0.2327388, abs=1e-7)
    assert high == pytest.approx(0.7672612, abs=1e-7)


def test_wilson_zero_successes() -> None:
    # k = 0: low is exactly 0, high = z^2 / (n + z^2) = 3.8414588 / 13.8414588 = 0.2775328
    low, high = wilson_interval(0, 10)
    assert low == 0.0
    assert high == pytest.approx(0.2775328, abs=1e-7)


def test_wilson_all_successes_mirrors_zero() -> None:
    # k = n: high is exactly 1, low = 1 - 0.2775328
    low, high = wilson_interval(10, 10)
    assert low == pytest.approx(0.7224672, abs=1e-7)
    assert high == 1.0


def test_wilson_single_trial() -> None:
    # n = 1, k = 1: low = 1 / (1 + z^2) = 1 / 4.8414588 = 0.2065493
    low, high = wilson_interval(1, 1)
    assert low == pytest.approx(0.2065493, abs=1e-7)
    assert high == 1.0


def test_wilson_no_trials_is_nan() -> None:
    low, high = wilson_interval(0, 0)
    assert math.isnan(low)
    assert math.isnan(high)


@pytest.mark.parametrize(
    ("successes", "n"), [(-1, 5), (6, 5), (0, -1), (2.0, 5), (True, 5), (1, 5.0)]
)
def test_wilson_rejects_impossible_counts(successes: Any, n: Any) -> None:
    with pytest.raises(MetricsError, match="0 <= successes <= n"):
        wilson_interval(successes, n)


def test_wilson_accepts_numpy_counts_and_rejects_bad_z() -> None:
    assert wilson_interval(np.int64(37), np.int64(53)) == wilson_interval(37, 53)
    for z in (0.0, -1.0, math.nan, math.inf):
        with pytest.raises(MetricsError, match="z = "):
            wilson_interval(1, 2, z=z)


def test_describe_by_hand() -> None:
    # sorted 2 4 4 4 5 5 7 9: mean 40/8 = 5; squared deviations 9 1 1 1 0 0 4 16 = 32,
    # sample SD sqrt(32/7) = 2.1380899; median (4 + 5)/2 = 4.5;
    # linear Q1 at position 7 * 0.25 = 1.75: 4 + 0.75 * (4 - 4) = 4;
    # Q3 at position 5.25: 5 + 0.25 * (7 - 5) = 5.5
    stats = describe([5, 9, 4, 2, 4, 7, 4, 5])
    assert stats.sd == pytest.approx(2.1380899, abs=1e-7)
    assert stats == Descriptive(
        n=8, mean=5.0, sd=stats.sd, median=4.5, q1=4.0, q3=5.5, minimum=2.0, maximum=9.0
    )


def test_describe_drops_non_finite_values() -> None:
    # finite 1 2 3 4 10: mean 4; deviations -3 -2 -1 0 6, squares sum 50, SD sqrt(50/4)
    # = 3.5355339; Q1 at position 1 = 2, median 3, Q3 at position 3 = 4
    stats = describe(np.array([1.0, math.nan, 10.0, 2.0, math.inf, 3.0, 4.0, -math.inf]))
    assert stats.n == 5
    assert stats.mean == 4.0
    assert stats.sd == pytest.approx(3.5355339, abs=1e-7)
    assert (stats.q1, stats.median, stats.q3) == (2.0, 3.0, 4.0)
    assert (stats.minimum, stats.maximum) == (1.0, 10.0)


def test_describe_one_value_has_no_sd() -> None:
    stats = describe([7.5, math.nan])
    assert stats.n == 1
    assert math.isnan(stats.sd)
    assert stats.mean == stats.median == stats.q1 == stats.q3 == stats.minimum == 7.5


def test_describe_nothing() -> None:
    stats = describe([])
    assert stats.n == 0
    assert all(math.isnan(v) for v in (stats.mean, stats.sd, stats.median, stats.maximum))

"""The paired test of a within-subject comparison: the Wilcoxon signed-rank test on one
value per participant in each of two conditions, its effect size and that effect size's
bootstrap interval.

The test: the differences d = first - second of the participants with a value in both
(pairs); pairs with d = 0 are dropped (Wilcoxon's convention, scipy's ``zero_method =
"wilcox"``); the rest are ranked by |d| (ties share their mean rank); T+ and T- are the
rank sums of the positive and negative differences. ``scipy.stats.wilcoxon`` gives the
two-sided p: exact when the differences are at most 50 and have no ties, else an exhaustive
permutation of the signs when they are at most 13, else the normal approximation (scipy's
``method = "auto"``). With n differences the smallest two-sided p possible is 2 / 2^n
(0.125 for four participants): a small study cannot reach p < 0.05 below six.

The effect size: the matched-pairs rank-biserial correlation r = (T+ - T-) / (T+ + T-)
(Kerby 2014), from -1 (every participant's first value is smaller) to +1 (every first
value larger); 0 when no pair differs. Its interval: the percentile bootstrap over
participants, ``resamples`` draws of the pairs with replacement from a generator seeded
with ``seed`` (numpy's ``default_rng``), r recomputed on each, the interval the
``(1 - confidence) / 2`` and ``(1 + confidence) / 2`` quantiles of the draws. With few
participants the draws take few distinct values and the interval is rough.

A test needs :data:`MIN_PAIRS` pairs and one difference that is not 0; short of that the
result says why in words (``missing``), with no statistic.
"""

from __future__ import annotations

import math
import statistics
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from workcell.errors import ConfigError
from workcell.settings import declared_problems, setting

WILCOXON_VERSION = "1"
MIN_PAIRS = 2
"""Participants with a value in both conditions that a test needs."""


@dataclass(frozen=True)
class PairedParams:
    """How the effect size's interval is drawn."""

    resamples: int = setting(
        2000,
        "bootstrap draws of the participants for the rank-biserial interval",
        unit="draws",
        low=100,
        high=100_000,
    )
    seed: int = setting(0, "seed of the bootstrap's generator", unit="1", low=0, high=2**32 - 1)
    confidence: float = setting(
        0.95, "the interval's confidence level", unit="share 0-1", low=0.5, high=0.999
    )

    def __post_init__(self) -> None:
        problems = declared_problems(self, "")
        if problems:
            raise ConfigError(problems)


@dataclass(frozen=True)
class PairedTest:
    """The Wilcoxon signed-rank test of ``first`` - ``second`` over the participants with a
    value in both. ``missing`` says in words why there is no test (then the statistics are
    NaN); the medians and ``n_pairs`` are given either way."""

    n_pairs: int
    n_nonzero: int
    median_first: float
    median_second: float
    median_difference: float
    t_plus: float
    t_minus: float
    p_value: float
    method: str
    """``exact``, ``permutation`` (ties among the differences) or ``normal``."""
    smallest_p: float
    """The smallest two-sided p the exact test can give with these many differences."""
    rank_biserial: float
    low: float
    high: float
    missing: str | None


def rank_biserial(differences: NDArray[np.float64]) -> NDArray[np.float64]:
    """r = (T+ - T-) / (T+ + T-) of each row of ``differences`` (zeros dropped before
    ranking; 0 for a row without a nonzero difference)."""
    d = np.atleast_2d(differences)
    magnitude = np.where(d == 0, np.nan, np.abs(d))
    from scipy.stats import rankdata  # noqa: PLC0415

    ranks = rankdata(magnitude, axis=1, nan_policy="omit")
    plus = np.nansum(np.where(d > 0, ranks, 0.0), axis=1)
    minus = np.nansum(np.where(d < 0, ranks, 0.0), axis=1)
    total = plus + minus
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(total > 0, (plus - minus) / np.where(total > 0, total, 1.0), 0.0)


def bootstrap_interval(
    differences: NDArray[np.float64], params: PairedParams
) -> tuple[float, float]:
    """The percentile bootstrap interval of the rank-biserial r over the participants."""
    rng = np.random.default_rng(params.seed)
    draws = rng.integers(0, len(differences), size=(params.resamples, len(differences)))
    values = rank_biserial(differences[draws])
    tail = (1.0 - params.confidence) / 2.0
    low, high = np.quantile(values, [tail, 1.0 - tail])
    return float(low), float(high)


def _method(nonzero: NDArray[np.float64]) -> str:
    ties = len(np.unique(np.abs(nonzero))) < len(nonzero)
    if len(nonzero) <= 50 and not ties:
        return "exact"
    return "permutation" if len(nonzero) <= 13 else "normal"


def _median(values: Sequence[float]) -> float:
    return float(statistics.median(values)) if values else math.nan


def paired_test(
    first: Sequence[float], second: Sequence[float], params: PairedParams
) -> PairedTest:
    """The test of the pairs ``(first[i], second[i])`` (pairs with a NaN are left out)."""
    pairs = [(a, b) for a, b in zip(first, second, strict=True) if math.isfinite(a + b)]
    a = [p[0] for p in pairs]
    b = [p[1] for p in pairs]
    d = np.array([x - y for x, y in pairs], dtype=float)
    nonzero = d[d != 0]
    n = len(nonzero)
    medians = (_median(a), _median(b), _median([float(x) for x in d]))
    nan = math.nan
    missing = None
    if len(pairs) < MIN_PAIRS:
        missing = (
            f"no test: it needs {MIN_PAIRS} participants with a value in both, "
            f"{'only ' if pairs else ''}{len(pairs)} {'has' if len(pairs) == 1 else 'have'} one"
        )
    elif n == 0:
        missing = f"no test: all {len(pairs)} participants have the same value in both"
    if missing is not None:
        return PairedTest(len(pairs), n, *medians, nan, nan, nan, "", nan, nan, nan, nan, missing)
    from scipy.stats import wilcoxon  # noqa: PLC0415

    (r,) = rank_biserial(d)
    low, high = bootstrap_interval(d, params)
    ranks = _signed_rank_sums(nonzero)
    result = wilcoxon(nonzero, alternative="two-sided", method="auto")
    return PairedTest(
        n_pairs=len(pairs),
        n_nonzero=n,
        median_first=medians[0],
        median_second=medians[1],
        median_difference=medians[2],
        t_plus=ranks[0],
        t_minus=ranks[1],
        p_value=float(result.pvalue),
        method=_method(nonzero),
        smallest_p=min(1.0, 2.0 / 2.0**n),
        rank_biserial=float(r),
        low=low,
        high=high,
        missing=None,
    )


def _signed_rank_sums(nonzero: NDArray[np.float64]) -> tuple[float, float]:
    from scipy.stats import rankdata  # noqa: PLC0415

    ranks = rankdata(np.abs(nonzero))
    return float(ranks[nonzero > 0].sum()), float(ranks[nonzero < 0].sum())

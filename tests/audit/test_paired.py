"""The within-subject comparison's paired test (:mod:`workcell.audit.wilcoxon`): the
Wilcoxon signed-rank p against every assignment of signs enumerated by hand, the
matched-pairs rank-biserial correlation against its definition, the bootstrap interval's
behaviour, and the words said instead of a test that cannot be run."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

from workcell.audit.paired_text import test_text as paired_text
from workcell.audit.wilcoxon import MIN_PAIRS, PairedParams, paired_test, rank_biserial
from workcell.errors import ConfigError

PARAMS = PairedParams()


def _ranks(magnitudes: list[float]) -> list[float]:
    """Ranks from 1, ties sharing their mean rank."""
    order = sorted(magnitudes)
    return [
        (order.index(m) + 1 + order.index(m) + order.count(m)) / 2 for m in magnitudes
    ]  # first and last position of m, averaged


def _t_sums(differences: list[float]) -> tuple[float, float]:
    nonzero = [d for d in differences if d != 0]
    ranks = _ranks([abs(d) for d in nonzero])
    plus = sum(r for r, d in zip(ranks, nonzero, strict=True) if d > 0)
    return plus, sum(ranks) - plus


def _exact_p_by_hand(differences: list[float]) -> float:
    """Two-sided: twice the smaller tail of T+ over all 2^n sign assignments of the ranks."""
    nonzero = [d for d in differences if d != 0]
    ranks = _ranks([abs(d) for d in nonzero])
    observed, _ = _t_sums(differences)
    sums = [
        sum(r for r, s in zip(ranks, signs, strict=True) if s)
        for signs in itertools.product((False, True), repeat=len(ranks))
    ]
    low = sum(t <= observed + 1e-9 for t in sums) / len(sums)
    high = sum(t >= observed - 1e-9 for t in sums) / len(sums)
    return min(1.0, 2 * min(low, high))


@pytest.mark.parametrize(
    ("first", "second"),
    [
        ([21.0, 25.5, 30.2, 28.0, 24.1], [24.0, 27.0, 29.0, 33.5, 30.0]),
        ([1.0, 2.0, 3.0, 4.0, 5.0, 6.0], [2.5, 1.5, 6.0, 7.5, 10.0, 12.0]),
        ([0.9, 0.5, 0.7, 1.0], [0.6, 0.85, 0.3, 0.2]),
    ],
)
def test_the_signed_rank_test_matches_every_sign_assignment_counted_by_hand(
    first: list[float], second: list[float]
) -> None:
    test = paired_test(first, second, PARAMS)
    differences = [a - b for a, b in zip(first, second, strict=True)]
    plus, minus = _t_sums(differences)
    assert (test.t_plus, test.t_minus) == pytest.approx((plus, minus))
    assert test.method == "exact"
    assert test.p_value == pytest.approx(_exact_p_by_hand(differences), rel=1e-9)
    assert test.rank_biserial == pytest.approx((plus - minus) / (plus + minus))
    assert test.n_pairs == test.n_nonzero == len(first)
    assert test.smallest_p == pytest.approx(2 / 2 ** len(first))
    assert test.median_difference == pytest.approx(float(np.median(differences)))
    assert test.low <= test.rank_biserial <= test.high
    assert test.missing is None


def test_zero_differences_are_dropped_and_ties_share_their_rank() -> None:
    first = [10.0, 12.0, 9.0, 11.0, 15.0, 7.0]
    second = [8.0, 12.0, 7.0, 12.0, 9.0, 6.0]  # differences 2, 0, 2, -1, 6, 1
    test = paired_test(first, second, PARAMS)
    assert (test.n_pairs, test.n_nonzero) == (6, 5)
    differences = [a - b for a, b in zip(first, second, strict=True)]
    plus, minus = _t_sums(differences)  # ranks of 2, 2, 1, 6, 1: 3.5, 3.5, 1.5, 5, 1.5
    assert (plus, minus) == (13.5, 1.5)
    assert (test.t_plus, test.t_minus) == (plus, minus)
    assert test.method == "permutation"  # ties: scipy permutes the signs exhaustively
    assert test.p_value == pytest.approx(_exact_p_by_hand(differences), rel=1e-9)
    assert test.rank_biserial == pytest.approx(12 / 15)


def test_the_rank_biserial_is_plus_one_when_every_first_value_is_larger() -> None:
    assert rank_biserial(np.array([3.0, 1.0, 2.0]))[0] == 1.0
    assert rank_biserial(np.array([-3.0, -1.0, 0.0]))[0] == -1.0
    assert rank_biserial(np.array([0.0, 0.0]))[0] == 0.0  # no pair differs: no shift
    rows = rank_biserial(np.array([[1.0, -2.0], [2.0, -1.0]]))
    assert rows.tolist() == pytest.approx([-1 / 3, 1 / 3])


def test_the_bootstrap_interval_resamples_participants_with_its_seed() -> None:
    first, second = [5.0, 6.0, 7.0, 8.0, 9.0], [4.0, 4.5, 8.0, 6.0, 6.5]
    test = paired_test(first, second, PARAMS)
    assert test.low < test.rank_biserial < test.high  # one participant goes the other way
    again = paired_test(first, second, PARAMS)
    assert (again.low, again.high) == (test.low, test.high)  # seeded: the same every time
    other = paired_test(first, second, PairedParams(seed=7))
    assert other.p_value == test.p_value and -1 <= other.low <= other.high <= 1
    narrow = paired_test(first, second, PairedParams(confidence=0.5))
    assert test.low <= narrow.low <= narrow.high <= test.high
    # every participant's first value larger: every draw gives r = 1
    same = paired_test([2.0, 3.0, 4.0], [1.0, 1.0, 1.0], PARAMS)
    assert (same.rank_biserial, same.low, same.high) == (1.0, 1.0, 1.0)


def test_a_test_that_cannot_be_run_is_said_in_words() -> None:
    one = paired_test([20.0, math.nan, 30.0], [25.0, 22.0, math.nan], PARAMS)
    assert one.n_pairs == 1 and math.isnan(one.p_value)
    assert one.missing == (
        f"no test: it needs {MIN_PAIRS} participants with a value in both, only 1 has one"
    )
    none = paired_test([math.nan], [1.0], PARAMS)
    needs = f"no test: it needs {MIN_PAIRS} participants with a value in both"
    assert none.missing == f"{needs}, 0 have one"
    same = paired_test([1.0, 0.5, 1.0], [1.0, 0.5, 1.0], PARAMS)
    assert same.missing == "no test: all 3 participants have the same value in both"
    texts = [
        paired_text("completion_time_s", one, 0.95),
        paired_text("completion_time_s", none, 0.95),
        paired_text("success_rate", same, 0.95),
    ]
    assert texts == [
        "median 20 s vs 25 s, difference -5 s; " + str(one.missing),
        str(none.missing),
        "median 100 % vs 100 %, difference +0 points; " + str(same.missing),
    ]
    assert not any("nan" in text for text in texts)


def test_bad_bootstrap_settings_are_refused_naming_the_setting() -> None:
    with pytest.raises(ConfigError, match="resamples"):
        PairedParams(resamples=3)
    with pytest.raises(ConfigError, match="confidence"):
        PairedParams(confidence=1.5)

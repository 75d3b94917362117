"""The audit's comparison (``workcell audit --by operator|condition``): Fisher's exact test
and the Mann-Whitney U test against values computed by hand (enumerating every table and
every split of the ranks), and the whole path on a real store with two conditions."""

from __future__ import annotations

import itertools
import json
import math
import statistics
from pathlib import Path

import pytest

from tests.audit.conftest import _collect
from workcell.audit.comparison import rank_test, success_test
from workcell.audit.stats import SuccessRate
from workcell.cli.main import EXIT_USAGE, main


def _rate(successes: int, n: int) -> SuccessRate:
    return SuccessRate(successes, n, successes / n if n else math.nan, 0.0, 1.0)


def _fisher_by_hand(a: int, b: int, c: int, d: int) -> float:
    """Two-sided Fisher p: the probability of every table with these margins that is no
    more likely than the observed one (hypergeometric)."""
    row1, col1, n = a + b, a + c, a + b + c + d

    def probability(x: int) -> float:
        return math.comb(col1, x) * math.comb(n - col1, row1 - x) / math.comb(n, row1)

    observed = probability(a)
    tables = range(max(0, row1 + col1 - n), min(row1, col1) + 1)
    return sum(p for x in tables if (p := probability(x)) <= observed * (1 + 1e-7))


def _u_by_hand(first: list[float], second: list[float]) -> float:
    return sum((x > y) + 0.5 * (x == y) for x in first for y in second)


def _exact_p_by_hand(first: list[float], second: list[float]) -> float:
    """Two-sided exact p: the share of all splits of the pooled values into groups of these
    sizes whose U is at least as far from n1 n2 / 2 as the observed U."""
    pooled = first + second
    centre = len(first) * len(second) / 2
    observed = abs(_u_by_hand(first, second) - centre)
    splits = list(itertools.combinations(range(len(pooled)), len(first)))
    extreme = 0
    for chosen in splits:
        a = [pooled[i] for i in chosen]
        b = [pooled[i] for i in range(len(pooled)) if i not in chosen]
        extreme += abs(_u_by_hand(a, b) - centre) >= observed - 1e-9
    return extreme / len(splits)


@pytest.mark.parametrize(("a", "n_a", "b", "n_b"), [(8, 10, 3, 10), (2, 2, 0, 2), (5, 9, 5, 6)])
def test_success_is_compared_by_fishers_exact_test(a: int, n_a: int, b: int, n_b: int) -> None:
    test = success_test(_rate(a, n_a), _rate(b, n_b))
    assert test.p_value == pytest.approx(_fisher_by_hand(a, n_a - a, b, n_b - b), rel=1e-9)
    assert test.risk_difference == pytest.approx(a / n_a - b / n_b)
    expected_odds = (a * (n_b - b)) / ((n_a - a) * b) if (n_a - a) * b else math.inf
    assert test.odds_ratio == pytest.approx(expected_odds)


def test_a_group_without_valid_trials_is_not_tested() -> None:
    test = success_test(_rate(3, 4), _rate(0, 0))
    assert math.isnan(test.p_value) and math.isnan(test.risk_difference)


@pytest.mark.parametrize(
    ("first", "second"),
    [
        ([3.0, 7.0, 9.0], [1.0, 4.0, 6.0, 8.0]),
        ([1.0, 2.0, 3.5], [4.0, 5.0, 6.0, 7.0]),
        ([21.2, 22.4, 21.9, 23.0], [38.0, 22.1, 60.5]),
    ],
)
def test_times_are_compared_by_the_mann_whitney_u_test(
    first: list[float], second: list[float]
) -> None:
    rank = rank_test("completion_time_s", first, second)
    u = _u_by_hand(first, second)
    assert rank.u == u
    assert rank.p_value == pytest.approx(_exact_p_by_hand(first, second), rel=1e-9)
    assert rank.rank_biserial == pytest.approx(2 * u / (len(first) * len(second)) - 1)
    assert (rank.n_first, rank.n_second) == (len(first), len(second))
    assert rank.median_first == pytest.approx(statistics.median(first))
    assert rank.median_second == pytest.approx(statistics.median(second))


def test_non_finite_values_are_left_out_and_an_empty_group_is_not_tested() -> None:
    rank = rank_test("path_length_m", [1.0, math.nan, 2.0], [math.nan])
    assert (rank.n_first, rank.n_second) == (2, 0)
    assert math.isnan(rank.p_value) and math.isnan(rank.u)
    assert rank.median_first == 1.5 and math.isnan(rank.median_second)


def _collect_into(store: Path, *args: str) -> None:
    run = _collect(store, *args)
    out, _ = run.communicate(timeout=300)
    assert run.returncode == 0, out


@pytest.fixture(scope="module")
def two_conditions(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """One store: the brisk expert in condition ``brisk`` (2 successes), then a slow one
    (skill 0.3, 15 s limit: 2 timeouts) in condition ``slow``."""
    store = tmp_path_factory.mktemp("conditions") / "study.sqlite"
    _collect_into(store, "--trials", "2", "--seed", "5", "--condition", "brisk")
    _collect_into(
        store,
        *("--trials", "2", "--seed", "6", "--skill", "0.3", "--condition", "slow"),
        *("--set", "task.time_limit_s=15"),
    )
    return store


def test_audit_by_condition_compares_the_conditions(
    two_conditions: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "report"
    assert (
        main(["audit", "--store", str(two_conditions), "--out", str(out), "--by", "condition"]) == 0
    )
    printed = capsys.readouterr().out
    assert "condition brisk: 2 trials, 2 valid (2 successes, 0 timeouts)" in printed
    assert "condition slow: 2 trials, 2 valid (0 successes, 2 timeouts)" in printed
    fisher = _fisher_by_hand(2, 0, 0, 2)
    assert f"brisk vs slow: success +100.0 points (Fisher p = {fisher:.3g})" in printed
    assert "not independent" in printed
    # the slow condition has no valid success: said in words, not as a median of nan
    assert "nan" not in printed
    assert "; completion time: no valid success in slow (median " in printed

    comparison = json.loads((out / "summary.json").read_text())["comparison"]
    assert comparison["by"] == "condition"
    # each operator ran one condition: a between-subject design, compared pooled
    assert (comparison["design"], comparison["paired"]) == ("between", None)
    assert "design: within" not in printed and "Wilcoxon" not in printed
    assert [g["value"] for g in comparison["groups"]] == ["brisk", "slow"]
    (pair,) = comparison["pairs"]
    assert pair["success"]["p_value"] == pytest.approx(fisher)
    assert pair["success"]["risk_difference"] == 1.0
    time = pair["metrics"]["completion_time_s"]
    assert (time["n_first"], time["n_second"], time["p_value"]) == (2, 0, None)
    assert 15 < time["median_first"] < 40
    curves = comparison["learning_curves"]
    assert [a["number"] for a in curves["expert"]] == [1, 2]
    assert [a["outcome"] for a in curves["expert-skill0.3"]] == ["timeout", "timeout"]
    assert "not independent" in comparison["caveat"]
    assert json.loads((out / "summary.json").read_text())["parameters"]["compare_by"] == "condition"

    report = (out / "report.html").read_text()
    assert "Comparison by condition" in report
    assert '<figure id="comparison">' in report and '<figure id="learning">' in report


def test_audit_without_by_has_no_comparison(two_conditions: Path, tmp_path: Path) -> None:
    assert main(["audit", "--store", str(two_conditions), "--out", str(tmp_path / "r")]) == 0
    summary = json.loads((tmp_path / "r" / "summary.json").read_text())
    assert "comparison" not in summary
    assert '<figure id="learning">' not in (tmp_path / "r" / "report.html").read_text()


def test_bad_by_and_bad_condition_are_one_error_each(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    store, out = str(tmp_path / "s.sqlite"), str(tmp_path / "out")
    assert main(["audit", "--store", store, "--out", out, "--by", "shoe-size"]) == EXIT_USAGE
    assert "--by: invalid choice: 'shoe-size'" in capsys.readouterr().err
    assert main(["collect", "--trials", "1", "--store", store, "--condition", "a b"]) == EXIT_USAGE
    err = capsys.readouterr().err.strip().splitlines()
    assert err == [
        "workcell: error: condition = 'a b': must be up to 64 letters, digits, '.', '_' or '-'"
    ]
    assert not Path(store).exists()

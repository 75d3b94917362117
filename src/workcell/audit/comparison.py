"""Comparing groups of trials: by operator (participants of a study, or a policy beside the
demonstrations it learned from) or by study condition (the session setting ``condition``).

Per group: the dispositions of all its trials, the success rate of its valid trials with
its Wilson 95 % interval, and the Table I metrics of its valid successes. Between every
two groups: Fisher's exact test (two-sided) on valid successes against valid failures,
with the risk difference (rate of the first minus rate of the second) and the sample odds
ratio; the Mann-Whitney U test (two-sided; exact for small samples without ties, else
the normal approximation, as scipy chooses) on the completion time and on the path length
of the valid successes, with U of the first group and the rank-biserial correlation
r = 2U / (n1 n2) - 1 (+1: every value of the first group is larger; 0: no shift).
Per participant, the learning curve: their trials in the order they ran (sessions by
creation, trials by index), numbered from 1.

Repeated trials of one person are not independent: the tests treat every trial as an
independent observation, so their p-values overstate the evidence when few people each
ran many trials. Read them as descriptions of these trials, not of a population.

By condition on a within-subject design (a study's, where every participant runs every
condition: :func:`workcell.audit.paired.design_of`) the conditions are compared within
participants instead (:mod:`workcell.audit.paired`: one value per participant and
condition, the Wilcoxon signed-rank test) and the pooled tests are not run; the groups are
still described pooled.
"""

from __future__ import annotations

import itertools
import math
import statistics
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, get_args

from workcell.audit.config import CompareBy
from workcell.audit.paired import Design, WithinSubject, design_of, within_subject
from workcell.audit.stats import GroupStats, SuccessRate, metric_values
from workcell.audit.study_progress import StudyProgress, study_progress
from workcell.audit.trial_audit import TrialAudit
from workcell.audit.wilcoxon import PairedParams

if TYPE_CHECKING:
    from workcell.audit.run import AuditResult

COMPARE_KEYS: tuple[str, ...] = get_args(CompareBy)
NO_CONDITION = "(none)"
"""The group of sessions recorded without a condition."""
RANKED_METRICS: dict[str, tuple[str, str]] = {
    "completion_time_s": ("completion time", "s"),
    "path_length_m": ("TCP path", "m"),
}
"""The valid successes' metrics compared by the Mann-Whitney U test: name and unit."""
CAVEAT = (
    "Repeated trials of one person are not independent: the tests treat every trial as an "
    "independent observation, so their p-values overstate the evidence when few people "
    "each ran many trials."
)


def group_of(trial: TrialAudit, by: CompareBy) -> str:
    """The value of ``by`` for one trial."""
    if by == "operator":
        return trial.session.operator_id
    return trial.session.condition or NO_CONDITION


@dataclass(frozen=True)
class SuccessTest:
    """Fisher's exact test between two groups' valid trials (NaN where a group has none)."""

    p_value: float
    risk_difference: float
    odds_ratio: float


@dataclass(frozen=True)
class RankTest:
    """The Mann-Whitney U test between two groups' values of ``metric`` (valid successes;
    NaN where a group has no finite value)."""

    metric: str
    n_first: int
    n_second: int
    median_first: float
    median_second: float
    u: float
    p_value: float
    rank_biserial: float


@dataclass(frozen=True)
class PairComparison:
    """Two groups compared: success by Fisher's exact test, metrics by Mann-Whitney U."""

    first: str
    second: str
    success: SuccessTest
    ranks: tuple[RankTest, ...]


@dataclass(frozen=True)
class Attempt:
    """One trial of a participant, numbered in the order they ran (from 1)."""

    number: int
    session_id: str
    trial_index: int
    outcome: str
    valid: bool
    completion_time_s: float


@dataclass(frozen=True)
class Comparison:
    """Every group of ``by``, every pair of groups (pooled; none on a within-subject
    design, compared in ``within`` instead), and every participant's learning curve."""

    by: CompareBy
    groups: tuple[GroupStats, ...]
    pairs: tuple[PairComparison, ...]
    learning: dict[str, tuple[Attempt, ...]]
    design: Design = "between"
    design_reason: str = ""
    within: WithinSubject | None = None
    study: StudyProgress | None = None


def success_test(first: SuccessRate, second: SuccessRate) -> SuccessTest:
    """Fisher's exact test (two-sided) on the 2x2 table of valid successes and failures."""
    if first.n == 0 or second.n == 0:
        return SuccessTest(math.nan, math.nan, math.nan)
    from scipy.stats import fisher_exact  # noqa: PLC0415

    table = [
        [first.successes, first.n - first.successes],
        [second.successes, second.n - second.successes],
    ]
    result = fisher_exact(table, alternative="two-sided")
    return SuccessTest(
        p_value=float(result.pvalue),
        risk_difference=first.rate - second.rate,
        odds_ratio=float(result.statistic),
    )


def rank_test(metric: str, first: Sequence[float], second: Sequence[float]) -> RankTest:
    """The Mann-Whitney U test (two-sided) between the finite values of two groups."""
    a = [v for v in first if math.isfinite(v)]
    b = [v for v in second if math.isfinite(v)]
    medians = (_median(a), _median(b))
    if not a or not b:
        return RankTest(metric, len(a), len(b), *medians, math.nan, math.nan, math.nan)
    from scipy.stats import mannwhitneyu  # noqa: PLC0415

    result = mannwhitneyu(a, b, alternative="two-sided")
    u = float(result.statistic)
    return RankTest(
        metric,
        len(a),
        len(b),
        *medians,
        u=u,
        p_value=float(result.pvalue),
        rank_biserial=2.0 * u / (len(a) * len(b)) - 1.0,
    )


def _median(values: Sequence[float]) -> float:
    return statistics.median(values) if values else math.nan


def learning_curves(trials: Sequence[TrialAudit]) -> dict[str, tuple[Attempt, ...]]:
    """Per participant (operator id), their trials in the order they ran."""
    curves: dict[str, list[Attempt]] = {}
    for trial in trials:
        attempts = curves.setdefault(trial.session.operator_id, [])
        time = trial.metrics.completion_time_s if trial.row.outcome == "success" else None
        attempts.append(
            Attempt(
                number=len(attempts) + 1,
                session_id=trial.row.session_id,
                trial_index=trial.row.trial_index,
                outcome=str(trial.row.outcome),
                valid=trial.disposition.included,
                completion_time_s=math.nan if time is None else float(time),
            )
        )
    return {operator: tuple(attempts) for operator, attempts in curves.items()}


def success_values(
    trials: Sequence[TrialAudit], by: CompareBy
) -> dict[str, dict[str, list[float]]]:
    """Per group of ``by``, per metric of :data:`RANKED_METRICS`, the values of its valid
    successes (NaN where undefined)."""
    values: dict[str, dict[str, list[float]]] = {}
    for trial in trials:
        group = values.setdefault(group_of(trial, by), {m: [] for m in RANKED_METRICS})
        if trial.valid_success:
            for metric in RANKED_METRICS:
                group[metric] += metric_values([trial], metric)
    return values


def compare(
    trials: Sequence[TrialAudit],
    by: CompareBy,
    study: StudyProgress | None = None,
    params: PairedParams | None = None,
) -> Comparison:
    """Groups of ``trials`` by ``by`` in order of first appearance, every pair of them
    compared (by condition: within participants on a within-subject design, else pooled),
    and the participants' learning curves."""
    values = list(dict.fromkeys(group_of(t, by) for t in trials))
    members = {value: [t for t in trials if group_of(t, by) == value] for value in values}
    groups = tuple(GroupStats.of(value, members[value]) for value in values)
    learning = learning_curves(trials)
    if by == "condition":
        design, reason = design_of(trials, study)
        if design == "within":
            within = within_subject(trials, reason, params or PairedParams(), study)
            return Comparison(by, groups, (), learning, design, reason, within, study)
    else:
        design, reason = "between", "participants are compared with each other"
    values_of = success_values(trials, by)
    pairs = []
    for first, second in itertools.combinations(groups, 2):
        a, b = values_of[first.value], values_of[second.value]
        ranks = tuple(rank_test(metric, a[metric], b[metric]) for metric in RANKED_METRICS)
        pairs.append(
            PairComparison(first.value, second.value, success_test(first.rate, second.rate), ranks)
        )
    return Comparison(by, groups, tuple(pairs), learning, design, reason, None, study)


def result_study(result: AuditResult) -> StudyProgress | None:
    """The progress of the study the audit was given (None: none given)."""
    study = result.config.study
    return None if study is None else study_progress(study, result.sessions)


def compare_result(result: AuditResult) -> Comparison | None:
    """The audit's comparison, as its configuration asks (None: none asked)."""
    by = result.config.compare_by
    if by == "none":
        return None
    return compare(result.trials, by, result_study(result), result.config.paired)

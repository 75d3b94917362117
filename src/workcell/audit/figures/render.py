"""Every figure of the report, in report order."""

from __future__ import annotations

from workcell.audit.comparison import compare_result, success_values
from workcell.audit.counts import DispositionCounts
from workcell.audit.figures.canvas import RenderedFigure
from workcell.audit.figures.comparison import draw_comparison, draw_learning
from workcell.audit.figures.distributions import draw_distributions
from workcell.audit.figures.flow import draw_flow
from workcell.audit.figures.ladder import draw_ladder
from workcell.audit.figures.outcomes import draw_outcomes
from workcell.audit.figures.paired import draw_paired
from workcell.audit.figures.sampling import draw_sampling
from workcell.audit.figures.trajectories import draw_trajectories
from workcell.audit.ladder import audit_ladder
from workcell.audit.run import AuditResult
from workcell.audit.stats import SuccessRate


def render_figures(result: AuditResult) -> list[RenderedFigure]:
    """Every figure in report order; the ladder's when an operator ran a task in several
    named worlds, the comparison's when the audit compares groups."""
    return [*_common_figures(result), *_ladder_figures(result), *_comparison_figures(result)]


def _ladder_figures(result: AuditResult) -> list[RenderedFigure]:
    rungs = audit_ladder(result.trials)
    if not rungs:
        return []
    return [
        RenderedFigure(
            "ladder",
            "Success across worlds",
            "Per operator, the success rate of its rollouts (complete trials) in each named "
            "world of its task, from narrow (D0) to broad (D2), with the Wilson 95 % "
            "interval; successes/rollouts beside each point.",
            draw_ladder(rungs),
        )
    ]


def _comparison_figures(result: AuditResult) -> list[RenderedFigure]:
    comparison = compare_result(result)
    if comparison is None:
        return []
    by = comparison.by
    paired = []
    if comparison.within is not None:
        paired.append(
            RenderedFigure(
                "paired",
                "Participants in each condition",
                "Per participant (one line each), in every condition: the success rate of "
                "their valid trials, and the median completion time and median TCP path of "
                "their valid successes (practice left out); the values the paired tests "
                "compare.",
                draw_paired(comparison.within),
            )
        )
    return [
        *paired,
        RenderedFigure(
            "comparison",
            f"Groups by {by}",
            f"Per {by}: success rate of the valid trials with its Wilson 95 % interval "
            "(successes/valid below), and the completion time and TCP-midpoint path of the "
            "valid successes (boxes: median and IQR; points: trials).",
            draw_comparison(comparison, success_values(result.trials, by)),
        ),
        RenderedFigure(
            "learning",
            "Learning curves",
            "Per participant (operator id), their trials in the order they ran: completion "
            "time of each success (crosses along the top: trials that did not succeed) and "
            "the success rate so far.",
            draw_learning(comparison),
        ),
    ]


def _common_figures(result: AuditResult) -> list[RenderedFigure]:
    trials = result.trials
    gap_periods = result.config.sampling.gap_periods
    return [
        RenderedFigure(
            "flow",
            "Trial disposition",
            "Raw trials to valid trials (paper Fig. 4): incomplete trials are excluded, "
            "successes with a disqualifying flag are excluded as low quality, timeouts (and "
            "trials a task's judge ended failed) are kept as valid failures (flagged ones "
            "marked); reviewer decisions are shown apart.",
            draw_flow(DispositionCounts.of(trials)),
        ),
        RenderedFigure(
            "outcomes",
            "Outcomes and success rate",
            "Outcome counts of the valid trials and the success rate with its Wilson 95 % "
            "confidence interval (paper Fig. 5A).",
            draw_outcomes(SuccessRate.of(trials), DispositionCounts.of(trials).valid_failures),
        ),
        RenderedFigure(
            "distributions",
            "Successful-trial metrics",
            "Recomputed metrics of the valid successful trials: boxes show the median and "
            "IQR, whiskers the 1.5-IQR rule, points individual trials (paper Fig. 5B-E).",
            draw_distributions(trials),
        ),
        RenderedFigure(
            "trajectories",
            "Trajectory morphology",
            f"Start-aligned floor-plane (x-y) TCP-midpoint paths of up to "
            f"{result.config.trajectories} temporally stratified valid successful trials "
            "(translated only), and their path lengths (paper Fig. 6).",
            draw_trajectories(result.trajectories, trials),
        ),
        RenderedFigure(
            "sampling",
            "Sampling continuity",
            "Realized sampling rate (wall and sim clock) and largest wall-clock gap of every "
            "trial in session order; hollow or grey points are excluded trials "
            "(paper §V-D).",
            draw_sampling(trials, gap_periods),
        ),
    ]

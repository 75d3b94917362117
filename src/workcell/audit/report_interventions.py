"""The report's "Corrections": per driver and per person who watched it, how often they
took over and what the corrected trials did against the driver alone
(:mod:`workcell.audit.interventions`)."""

from __future__ import annotations

from collections.abc import Sequence

from workcell.audit.html_parts import number, table
from workcell.audit.interventions import INTERVENTIONS_VERSION, InterventionGroup, Rate
from workcell.audit.report_sections import percent_interval

HEADER = (
    "driver",
    "person",
    "rollouts",
    "take-overs per trial",
    "corrected share of frames",
    "driver alone: successes / rollouts, Wilson 95 %",
    "with corrections: successes / rollouts, Wilson 95 %",
    "interrupted",
)


def _rate(rate: Rate) -> str:
    if not rate.n:
        return "no rollout"
    return f"{rate.successes}/{rate.n}, {percent_interval(rate.rate, rate.low, rate.high)}"


def group_cells(group: InterventionGroup) -> tuple[object, ...]:
    return (
        group.driver,
        group.person or "everyone",
        group.rollouts,
        number(group.interventions_per_trial, 2),
        number(100 * group.corrected_share, 1) + " %",
        _rate(group.alone),
        _rate(group.corrected),
        group.interrupted,
    )


def interventions_section(groups: Sequence[InterventionGroup]) -> str:
    """The section, or nothing when no trial had an autonomous driver."""
    if not groups:
        return ""
    return (
        "<h3>Corrections</h3>"
        f"<p>Trials an autonomous driver drove while a person watched and could take over "
        f"(definitions v{INTERVENTIONS_VERSION}), per driver and per person: rollouts are "
        "the complete trials; take-overs per trial count the person's take-overs; the "
        "corrected share is the share of the rollouts' time (and so of their frames) the "
        "person drove; success is compared between the rollouts nobody took over (the "
        "driver alone) and those taken over at least once (with corrections). A person "
        "takes over where the driver goes wrong, so the two are not a controlled "
        "comparison.</p>" + table(HEADER, [group_cells(g) for g in groups])
    )

"""The report's "Across worlds": the generalization ladder, one row per operator, task and
named world (:mod:`workcell.audit.ladder`), above its figure."""

from __future__ import annotations

from collections.abc import Sequence

from workcell.audit.html_parts import number, table
from workcell.audit.ladder import LADDER_VERSION, Rung
from workcell.audit.report_sections import percent_interval
from workcell.audit.task_stages import counts_text

HEADER = (
    "operator",
    "task",
    "world",
    "successes / rollouts",
    "success rate, Wilson 95 %",
    "median completion time of successes (s)",
    "stage reached",
    "interrupted",
)


def rung_cells(rung: Rung) -> tuple[object, ...]:
    """One rung as the table's cells."""
    rate = percent_interval(rung.rate, rung.low, rung.high) if rung.rollouts else "no rollout"
    return (
        rung.operator,
        rung.task,
        rung.world,
        f"{rung.successes}/{rung.rollouts}",
        rate,
        number(rung.median_completion_s, 2),
        counts_text(rung.stages),
        rung.interrupted,
    )


def ladder_section(rungs: Sequence[Rung], figure: str) -> str:
    """The section, or nothing when no operator ran a task in more than one named world."""
    if not rungs:
        return ""
    return (
        "<h3>Across worlds</h3>"
        f"<p>Each operator's trials per named world of their task, from narrow (D0) to broad "
        f"(D2) (ladder definition v{LADDER_VERSION}): rollouts are the complete trials "
        "(interrupted ones are counted apart); success is the trial's outcome, whatever its "
        "quality flags or a reviewer's decision, with its Wilson 95 % interval; the "
        "completion time is the median of the successes'; the stage reached counts the "
        "rollouts at the furthest stage of the task each got to. <code>workcell evaluate"
        "</code> prints the same table for the trials it recorded.</p>"
        + table(HEADER, [rung_cells(r) for r in rungs])
        + figure
    )

"""The report's "How far trials got": every trial's furthest task stage, by operator."""

from __future__ import annotations

from collections.abc import Sequence

from workcell.audit.html_parts import esc, table
from workcell.audit.stats import GroupStats, task_stages_of
from workcell.audit.task_stages import LIFT_M, TASK_STAGES, TASK_STAGES_VERSION, TaskStage, at_least
from workcell.audit.trial_audit import TrialAudit


def _row(label: str, counts: dict[TaskStage, int]) -> tuple[object, ...]:
    reached = at_least(counts)
    total = reached["none"]
    cells = [
        f"{reached[s]} ({100 * reached[s] / total:.0f} %)" if total else "0"
        for s in TASK_STAGES[1:]
    ]
    return (label, total, *cells)


def stages_section(trials: Sequence[TrialAudit], operators: Sequence[GroupStats]) -> str:
    """How many trials reached each stage of the task (or went further), over all trials
    and per operator when there is more than one."""
    rows = [_row("all trials", task_stages_of(trials))]
    rows += [_row(f"operator {g.value}", g.task_stages) for g in operators]
    header = ("trials", "n", *(f"{s.replace('_', ' ')}" for s in TASK_STAGES[1:]))
    return (
        "<h3>How far trials got</h3>"
        f"<p>Trials that reached each stage of the task or went further (definition "
        f"v{esc(TASK_STAGES_VERSION)}): a gripper touched a box, both pads closed on it, it "
        f"was lifted {LIFT_M * 100:.0f} cm, carried over the delivery zone, delivered. A "
        "timeout that carried its box over the zone is not one that never moved; every "
        "trial counts here, valid or not.</p>" + table(header, rows)
    )

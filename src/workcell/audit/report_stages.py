"""The report's "How far trials got": every trial's furthest stage of its own task, one
table per task, by operator (:mod:`workcell.audit.task_funnel`)."""

from __future__ import annotations

from collections.abc import Sequence

from workcell.audit.html_parts import esc, table
from workcell.audit.stats import GroupStats
from workcell.audit.task_funnel import TaskFunnel, task_funnels
from workcell.audit.task_stages import FRAMES_TASK, at_least
from workcell.audit.trial_audit import TrialAudit
from workcell.tasks.box_transfer.stages import FRAME_STAGES_TEXT


def _row(label: str, counts: dict[str, int], stages: tuple[str, ...]) -> tuple[object, ...]:
    reached = at_least(counts)
    total = sum(counts.values())
    cells = [
        f"{reached.get(s, 0)} ({100 * reached.get(s, 0) / total:.0f} %)" if total else "0"
        for s in stages[1:]
    ]
    return (label, total, *cells)


def _funnel(funnel: TaskFunnel, titled: bool) -> str:
    stages = funnel.stages
    rows = [_row("all trials", funnel.ended_at, stages)]
    rows += [_row(f"operator {op}", counts, stages) for op, counts in funnel.by_operator]
    header = ("trials", "n", *(s.replace("_", " ") for s in stages[1:]))
    what = (
        FRAME_STAGES_TEXT
        if funnel.task == FRAMES_TASK
        else "as the task's judge said (its stages: "
        + ", ".join(esc(s) for s in stages)
        + ("" if funnel.loaded else "; the task could not be loaded here, so in the order seen")
        + ")"
    )
    unknown = (
        f" {funnel.unknown} of its trials say no stage (recorded before trials kept their "
        "stage) and count nowhere."
        if funnel.unknown
        else ""
    )
    title = f"<h4>{esc(funnel.task)}</h4>" if titled else ""
    return (
        f"{title}<p>Trials that reached each stage of the task or went further {what}; "
        f"every trial counts here, valid or not.{unknown}</p>" + table(header, rows)
    )


def stages_section(trials: Sequence[TrialAudit], operators: Sequence[GroupStats]) -> str:
    """How many trials reached each stage of their task (or went further), one table per
    task, over all its trials and per operator when there is more than one (``operators``
    is kept for the caller; each task's operators are its own trials')."""
    del operators
    funnels = task_funnels(trials)
    titled = len(funnels) > 1 or any(f.task != FRAMES_TASK for f in funnels)
    return "<h3>How far trials got</h3>" + "".join(_funnel(f, titled) for f in funnels)

"""How far trials got, per task: each trial counted among its own task's stages.

A store may hold trials of several tasks (``task.kind``: box transfer, a task of one's
own); each task names its stages in order (:attr:`workcell.tasks.Task.stages`), so the
audit shows one funnel per task. A task is loaded by its recorded name
(:func:`workcell.tasks.registry.task_class`); one that cannot be loaded here (its module
is not importable) is shown with the stages its trials recorded, in the order first seen.
Box transfer's stages are read without loading the task (an audit of box transfer loads no
physics); another task's module is imported.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from functools import cache

from workcell.audit.task_stages import FRAMES_TASK, TASK_STAGES, at_least, stage_counts
from workcell.audit.trial_audit import TrialAudit
from workcell.errors import ConfigError


@cache
def declared_stages(kind: str) -> tuple[str, ...] | None:
    """The stages the task ``kind`` declares, in order; None when it cannot be loaded."""
    if kind == FRAMES_TASK:
        return TASK_STAGES
    from workcell.tasks.registry import task_class  # noqa: PLC0415 (loads the task's physics)

    try:
        return tuple(task_class(kind).stages)
    except ConfigError:
        return None


@dataclass(frozen=True)
class TaskFunnel:
    """The trials of one task: how many ended at each of its stages (in order), how many
    say no stage, and the same per operator."""

    task: str
    stages: tuple[str, ...]
    loaded: bool
    """Whether the stages are the task's own (else those its trials recorded)."""
    ended_at: dict[str, int]
    unknown: int
    """Trials whose stage nothing says (a trial of a task other than box transfer recorded
    before schema version 5, or never closed)."""
    by_operator: tuple[tuple[str, dict[str, int]], ...]

    @property
    def trials(self) -> int:
        return sum(self.ended_at.values()) + self.unknown


def _stages_of(kind: str, trials: Sequence[TrialAudit]) -> tuple[tuple[str, ...], bool]:
    stages = declared_stages(kind)
    if stages is not None:
        return stages, True
    seen = dict.fromkeys(t.task_stage for t in trials if t.task_stage is not None)
    return tuple(s for s in seen if s is not None), False


def _by_task(trials: Sequence[TrialAudit]) -> dict[str, list[TrialAudit]]:
    """The trials of each task, the tasks in order of first appearance."""
    out: dict[str, list[TrialAudit]] = {}
    for trial in trials:
        out.setdefault(trial.task, []).append(trial)
    return out


def _ended(trials: Sequence[TrialAudit], order: Sequence[str]) -> dict[str, int]:
    return stage_counts((t.task_stage for t in trials if t.task_stage is not None), order)


def trial_stage_counts(trials: Sequence[TrialAudit]) -> dict[str, int]:
    """How many ``trials`` ended at each stage; trials without a stage count nowhere. The
    stages are their task's in order; for trials of several tasks, each task's in turn (a
    stage an earlier task named keeps its place: ``none``, ``touched``...); box transfer's
    for no trials."""
    order: dict[str, None] = {}
    for kind, mine in _by_task(trials).items():
        order.update(dict.fromkeys(_stages_of(kind, mine)[0]))
    return _ended(trials, tuple(order) or TASK_STAGES)


def trial_stages_reached(trials: Sequence[TrialAudit]) -> dict[str, int]:
    """How many ``trials`` reached each stage of :func:`trial_stage_counts` or went further
    in their own task's order: for trials of several tasks, each task's
    :func:`~workcell.audit.task_stages.at_least` summed (a palletize trial that placed a
    box reached ``grasped``; a box transfer trial that finished never reached
    ``placed_1``)."""
    reached = dict.fromkeys(trial_stage_counts(trials), 0)
    for kind, mine in _by_task(trials).items():
        for stage, n in at_least(_ended(mine, _stages_of(kind, mine)[0])).items():
            reached[stage] += n
    return reached


def task_funnels(trials: Sequence[TrialAudit]) -> list[TaskFunnel]:
    """One funnel per task, in order of first appearance."""
    out: list[TaskFunnel] = []
    for kind in dict.fromkeys(t.task for t in trials):
        mine = [t for t in trials if t.task == kind]
        stages, loaded = _stages_of(kind, mine)
        operators = dict.fromkeys(t.session.operator_id for t in mine)

        def ended(group: Sequence[TrialAudit], order: tuple[str, ...] = stages) -> dict[str, int]:
            return stage_counts((t.task_stage for t in group if t.task_stage is not None), order)

        out.append(
            TaskFunnel(
                task=kind,
                stages=stages,
                loaded=loaded,
                ended_at=ended(mine),
                unknown=sum(t.task_stage is None for t in mine),
                by_operator=tuple(
                    (op, ended([t for t in mine if t.session.operator_id == op]))
                    for op in operators
                )
                if len(operators) > 1
                else (),
            )
        )
    return out

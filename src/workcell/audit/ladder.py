"""The generalization ladder: how one operator does in each of its task's named worlds.

A policy evaluated in D0, D1 and D2 (``workcell evaluate``), or the expert beside it, is a
set of trials of one operator in several named worlds (each trial's ``world`` column,
schema version 5). Per operator, task and world, a rung counts the **rollouts**: the
complete trials (every outcome but ``interrupted``; an interrupted trial never ran to an
end its task or its clock decided, so it is counted apart). Of those:

- success: the trial's outcome, ``success`` (quality flags and reviewers' decisions are
  about demonstrations, not about whether the operator did the task, so they do not
  change a rung), with its Wilson 95 % interval;
- completion time: the median of the successes' completion times (s of sim time);
- stage reached: how many rollouts ended at each of the task's stages, in the task's
  order (:mod:`workcell.audit.task_funnel`).

The audit computes the rungs from its trials (completion time recomputed from the frames,
the stage its stage pass read), ``workcell evaluate`` from the rows it recorded (the stored
completion time, the recorded stage): the numbers are the same, one function makes them.
"""

from __future__ import annotations

import math
import statistics
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

from workcell.audit.task_funnel import declared_stages
from workcell.audit.task_stages import stage_counts
from workcell.audit.trial_audit import TrialAudit
from workcell.metrics import wilson_interval

LADDER_VERSION = 1
"""The definition of a rung above; a change of it is a new version."""
WORLD_ORDER: tuple[str, ...] = ("D0", "D1", "D2")
"""Named worlds from narrow to broad (:data:`workcell.tasks.worlds.WORLDS`)."""


@dataclass(frozen=True)
class LadderTrial:
    """What a rung needs of one trial."""

    operator: str
    task: str
    world: str | None
    """``D0``, ``D1``, ``D2``; None for ranges of no named world (left off the ladder)."""
    outcome: str | None
    completion_time_s: float | None
    stage: str | None


@dataclass(frozen=True)
class Rung:
    """One operator's rollouts of one task in one named world."""

    operator: str
    task: str
    world: str
    rollouts: int
    """Complete trials (every outcome but ``interrupted``)."""
    successes: int
    interrupted: int
    """Trials interrupted, not counted in :attr:`rollouts`."""
    rate: float
    """Successes per rollout (NaN for none)."""
    low: float
    high: float
    """The Wilson 95 % interval of :attr:`rate` (NaN for no rollout)."""
    median_completion_s: float
    """Median completion time of the successes (NaN for none)."""
    stages: dict[str, int]
    """Rollouts that ended at each of the task's stages, in the task's order."""


def _median(values: Sequence[float]) -> float:
    finite = [v for v in values if math.isfinite(v)]
    return float(statistics.median(finite)) if finite else math.nan


def rung(operator: str, task: str, world: str, trials: Sequence[LadderTrial]) -> Rung:
    """The rung of ``trials`` (all of ``operator``'s ``task`` in ``world``)."""
    complete = [t for t in trials if t.outcome is not None and t.outcome != "interrupted"]
    successes = [t for t in complete if t.outcome == "success"]
    low, high = wilson_interval(len(successes), len(complete))
    times = [t.completion_time_s for t in successes if t.completion_time_s is not None]
    order = declared_stages(task) or ()
    return Rung(
        operator=operator,
        task=task,
        world=world,
        rollouts=len(complete),
        successes=len(successes),
        interrupted=len(trials) - len(complete),
        rate=len(successes) / len(complete) if complete else math.nan,
        low=low,
        high=high,
        median_completion_s=_median(times),
        stages=stage_counts((t.stage for t in complete if t.stage is not None), order),
    )


def ladder(trials: Iterable[LadderTrial]) -> list[Rung]:
    """Every (operator, task, named world) of ``trials``: operators and tasks in order of
    first appearance, worlds from narrow to broad."""
    groups: dict[tuple[str, str], dict[str, list[LadderTrial]]] = {}
    for trial in trials:
        if trial.world is None or trial.world not in WORLD_ORDER:
            continue
        groups.setdefault((trial.operator, trial.task), {}).setdefault(trial.world, []).append(
            trial
        )
    return [
        rung(operator, task, world, worlds[world])
        for (operator, task), worlds in groups.items()
        for world in WORLD_ORDER
        if world in worlds
    ]


def climbs(rungs: Sequence[Rung]) -> bool:
    """Whether the rungs make a ladder worth drawing: some operator ran one task in more
    than one named world."""
    seen: dict[tuple[str, str], int] = {}
    for r in rungs:
        seen[(r.operator, r.task)] = seen.get((r.operator, r.task), 0) + 1
    return any(count > 1 for count in seen.values())


def audited_trial(trial: TrialAudit) -> LadderTrial:
    """One audited trial as the ladder reads it."""
    return LadderTrial(
        operator=trial.session.operator_id,
        task=trial.task,
        world=trial.row.world,
        outcome=trial.row.outcome,
        completion_time_s=trial.metrics.completion_time_s,
        stage=trial.task_stage,
    )


def audit_ladder(trials: Sequence[TrialAudit]) -> list[Rung]:
    """The ladder of an audit's trials; empty unless it :func:`climbs`."""
    rungs = ladder(audited_trial(t) for t in trials)
    return rungs if climbs(rungs) else []

"""Where a participant is in their plan, read from the store: a planned session is done
when the store holds a completed session of that participant in that condition with that
session seed, or (a collection step) when its sessions together ended every planned trial.
A step stopped part way (the participant's stop, a dropped link, a stopped server) goes on
in a new session; a collection step's new session starts at the trial after the last one
its earlier sessions ended (:func:`resume_point`), so the trials done are not run again;
a practice or challenge step runs again whole. The interrupted session stays in the store,
as every recorded session does."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from workcell.record.entries import SessionRecord, TrialRecord
from workcell.study.plan import PlannedSession
from workcell.task.runner import trial_seed


def done_by(
    planned: PlannedSession, operator_id: str, condition: str, seed: int | None, status: str
) -> bool:
    """Whether a session of ``operator_id`` in ``condition`` with ``seed`` and ``status``
    completes ``planned``."""
    config = planned.config
    return (
        status == "completed"
        and operator_id == config.operator_id
        and seed == config.seed
        and condition == config.condition
    )


def _of_step(planned: PlannedSession, sessions: Sequence[SessionRecord]) -> list[SessionRecord]:
    config = planned.config
    return [
        s
        for s in sessions
        if s.operator_id == config.operator_id
        and s.seed == config.seed
        and s.parameters.get("condition") == config.condition
    ]


def is_done(
    planned: PlannedSession,
    sessions: Sequence[SessionRecord],
    trials: Sequence[TrialRecord] = (),
) -> bool:
    if any(s.status == "completed" for s in _of_step(planned, sessions)):
        return True
    task = planned.config.task
    return bool(task.trials) and resume_point(planned, sessions, trials) >= task.trials


def resume_point(
    planned: PlannedSession, sessions: Sequence[SessionRecord], trials: Sequence[TrialRecord]
) -> int:
    """The trial index a collection step's next session starts at: one after the last
    planned trial its earlier sessions ended with an outcome (not interrupted); 0 when none
    did, or for another mode or a step without a number of trials. A planned trial is
    known by its world's seed (:func:`~workcell.task.runner.trial_seed` of the step's
    session seed and the trial's index), as the store numbers each session's trials
    from 0."""
    task = planned.config.task
    if task.mode != "collection" or not task.trials:
        return 0
    index_of = {trial_seed(planned.config.seed, k): k for k in range(task.trials)}
    ids = {s.session_id for s in _of_step(planned, sessions)}
    ended = [
        index_of[t.trial_seed]
        for t in trials
        if t.session_id in ids
        and t.outcome is not None
        and t.outcome != "interrupted"
        and t.trial_seed in index_of
    ]
    return max(ended) + 1 if ended else 0


def remaining(plan: Sequence[PlannedSession], store: Path) -> list[PlannedSession]:
    """The planned sessions the store at ``store`` does not hold completed (all of them when
    there is no store yet)."""
    if not store.exists():
        return list(plan)
    from workcell.record.store import Store  # noqa: PLC0415

    with Store.open(store, writer=False) as reader:
        sessions, trials = reader.sessions(), reader.trials()
    return [planned for planned in plan if not is_done(planned, sessions, trials)]

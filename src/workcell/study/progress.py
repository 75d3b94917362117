"""Where a participant is in their plan, read from the store: a planned session is done
when the store holds a completed session of that participant in that condition with that
session seed. An interrupted session (a dropped link, a stopped server) is run again as a
new session; the interrupted one stays in the store, as every recorded session does."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from workcell.record.entries import SessionRecord
from workcell.study.plan import PlannedSession


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


def is_done(planned: PlannedSession, sessions: Sequence[SessionRecord]) -> bool:
    return any(
        done_by(planned, s.operator_id, s.parameters.get("condition", ""), s.seed, s.status)
        for s in sessions
    )


def remaining(plan: Sequence[PlannedSession], store: Path) -> list[PlannedSession]:
    """The planned sessions the store at ``store`` does not hold completed (all of them when
    there is no store yet)."""
    if not store.exists():
        return list(plan)
    from workcell.record.store import Store  # noqa: PLC0415

    with Store.open(store, writer=False) as reader:
        sessions = reader.sessions()
    return [planned for planned in plan if not is_done(planned, sessions)]

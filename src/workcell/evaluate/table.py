"""The table ``workcell evaluate`` prints: the ladder of the trials it recorded, read back
from the store (:mod:`workcell.audit.ladder`, the rungs the audit draws)."""

from __future__ import annotations

import math
from collections.abc import Collection, Sequence
from pathlib import Path

from workcell.audit.ladder import LadderTrial, Rung, ladder
from workcell.audit.store_source import StoreSource
from workcell.audit.task_stages import counts_text

HEADER = ("world", "successes", "success rate [Wilson 95 %]", "median time (s)", "stage reached")


def recorded_rungs(store: Path, session_ids: Collection[str]) -> list[Rung]:
    """The rungs of the trials of ``session_ids`` in ``store``, as stored."""
    source = StoreSource(store)
    try:
        sessions = {s.session_id: s for s in source.sessions() if s.session_id in session_ids}
        trials = [t for t in source.trials() if t.session_id in sessions]
    finally:
        source.close()
    return ladder(
        LadderTrial(
            operator=sessions[t.session_id].operator_id,
            task=t.task or sessions[t.session_id].task,
            world=t.world,
            outcome=t.outcome,
            completion_time_s=t.stored.get("completion_time_s"),
            stage=t.recorded_stage,
        )
        for t in trials
    )


def _rate(rung: Rung) -> str:
    if not rung.rollouts:
        return "no rollout"
    return f"{100 * rung.rate:5.1f} % [{100 * rung.low:.1f}, {100 * rung.high:.1f}]"


def _cells(rung: Rung) -> tuple[str, ...]:
    median = "-" if math.isnan(rung.median_completion_s) else f"{rung.median_completion_s:.2f}"
    stages = counts_text(rung.stages)
    if rung.interrupted:
        stages += f" ({rung.interrupted} interrupted, not counted)"
    return (rung.world, f"{rung.successes}/{rung.rollouts}", _rate(rung), median, stages)


def table_lines(rungs: Sequence[Rung]) -> list[str]:
    """The table: a header and one aligned row per world."""
    rows = [HEADER, *(_cells(r) for r in rungs)]
    widths = [max(len(row[i]) for row in rows) for i in range(len(HEADER) - 1)]
    return [
        "  ".join([*(cell.ljust(w) for cell, w in zip(row, widths, strict=False)), row[-1]])
        for row in rows
    ]

"""What verification reports: one :class:`IntegrityFinding` per problem in a store or an
export, naming where it is (the audit's quality findings are :mod:`workcell.audit.findings`)."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

SHOWN_ROWS = 5
"""A problem in many frames names the first few and counts the rest."""


@dataclass(frozen=True)
class IntegrityFinding:
    """One problem: in which store (or export directory), table (or file) and row."""

    store: str
    table: str
    row: str
    problem: str

    def __str__(self) -> str:
        where = f"{self.table} {self.row}" if self.row else self.table
        return f"{self.store}: {where}: {self.problem}"


def frames_label(trial_id: str, indices: Sequence[int]) -> str:
    """``trial T frame 3``, or ``trial T frames 3, 4, 9, 10, 11 and 40 more``."""
    if len(indices) == 1:
        return f"trial {trial_id} frame {indices[0]}"
    shown = ", ".join(str(i) for i in indices[:SHOWN_ROWS])
    more = len(indices) - SHOWN_ROWS
    return f"trial {trial_id} frames {shown}{f' and {more} more' if more > 0 else ''}"

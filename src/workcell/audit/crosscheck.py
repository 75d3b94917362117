"""Cross-check: each metric recomputed from frames against the value stored on the trial.

Two values agree when both are undefined (NULL / NaN), or when both are numbers with
|stored - recomputed| <= relative * max(|stored|, |recomputed|) + absolute. The recorder
stores what :func:`workcell.metrics.compute_trial_metrics` returned, so an honest store
agrees to the last bit; the tolerance only absorbs a different summation order.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from workcell.audit.rows import TrialRow
from workcell.checks import positive
from workcell.errors import ConfigError
from workcell.metrics import TrialMetrics
from workcell.metrics.definitions import RECOMPUTED_COLUMNS

CROSSCHECKED: tuple[str, ...] = RECOMPUTED_COLUMNS
"""The stored trial columns a recomputation checks (n_frames exactly)."""


@dataclass(frozen=True)
class Tolerance:
    relative: float = 1e-9
    absolute: float = 1e-12

    def __post_init__(self) -> None:
        problems = positive("crosscheck.relative", self.relative)
        problems += positive("crosscheck.absolute", self.absolute)
        if problems:
            raise ConfigError(problems)

    def agree(self, stored: float | None, recomputed: float | None) -> bool:
        a = math.nan if stored is None else float(stored)
        b = math.nan if recomputed is None else float(recomputed)
        if math.isnan(a) or math.isnan(b):
            return math.isnan(a) and math.isnan(b)
        if math.isinf(a) or math.isinf(b):
            return a == b
        return abs(a - b) <= self.relative * max(abs(a), abs(b)) + self.absolute


@dataclass(frozen=True)
class Mismatch:
    """A stored metric the frames do not reproduce."""

    metric: str
    stored: float | int | None
    recomputed: float | int | None

    def describe(self) -> str:
        return f"{self.metric}: stored {self.stored!r}, recomputed {self.recomputed!r}"


def crosscheck(row: TrialRow, metrics: TrialMetrics, tolerance: Tolerance) -> tuple[Mismatch, ...]:
    """Every disagreement between ``row``'s stored metrics and ``metrics``; none for a
    trial still open (it has no stored metrics yet)."""
    if row.outcome is None:
        return ()
    found = []
    for name in CROSSCHECKED:
        stored = row.stored[name]
        recomputed = getattr(metrics, name)
        exact = name == "n_frames"
        same = stored == recomputed if exact else tolerance.agree(stored, recomputed)
        if not same:
            found.append(Mismatch(name, stored, recomputed))
    return tuple(found)

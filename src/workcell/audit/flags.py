"""Quality flags: what a detector found in one trial's frames.

A flag never changes a trial's outcome. A disqualifying flag excludes a *successful* trial
as low quality (paper Fig. 4); a timeout keeps its place as a valid failure and is marked.
"""

from __future__ import annotations

from dataclasses import dataclass

ARM_OSCILLATION = "arm_oscillation"
SAMPLING_GAP = "sampling_gap"
NON_MONOTONIC = "non_monotonic"
NONFINITE = "nonfinite"
SLOW = "slow"

FLAG_NAMES: tuple[str, ...] = (ARM_OSCILLATION, SAMPLING_GAP, NON_MONOTONIC, NONFINITE, SLOW)
"""Every flag the audit can raise, in report order."""


@dataclass(frozen=True)
class Flag:
    """One finding of a detector: its ``name`` (one of FLAG_NAMES), a one-line ``detail``
    with where and how much, and whether it disqualifies a successful trial."""

    name: str
    detail: str
    disqualifying: bool

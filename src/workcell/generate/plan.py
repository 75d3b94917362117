"""What a generation replays: its source trials, cut into segments, and its operator id."""

from __future__ import annotations

import hashlib
from collections.abc import Sequence
from dataclasses import dataclass

from workcell.generate.segments import Segment, segment
from workcell.generate.source import SourceTrial
from workcell.tasks.task import SegmentReferences

OPERATOR_PREFIX = "generated-"
HASH_CHARS = 10


def generated_operator_id(source_ids: Sequence[str]) -> str:
    """``generated-`` and a short hash of the sorted source trial ids: the same source set
    always generates as the same operator."""
    digest = hashlib.sha256("\n".join(sorted(source_ids)).encode()).hexdigest()
    return OPERATOR_PREFIX + digest[:HASH_CHARS]


@dataclass(frozen=True)
class GenerationPlan:
    """The source trials and their segments (frozen and picklable, for worker processes)."""

    task: str
    """The task whose trials these are (its registered name)."""
    sources: tuple[SourceTrial, ...]
    segments: tuple[tuple[Segment, ...], ...]
    """Each source trial's segments, in the order of :attr:`sources`."""
    retarget: bool = True
    """Move each segment with its object (False: replay the source motion where it was
    recorded, the ablation ``bench/generate_worlds.py --naive`` measures)."""

    @staticmethod
    def of(
        task: str,
        sources: Sequence[SourceTrial],
        references: SegmentReferences,
        retarget: bool = True,
    ) -> GenerationPlan:
        segments = tuple(segment(s, references) for s in sources)
        return GenerationPlan(task, tuple(sources), segments, retarget)

    @property
    def operator_id(self) -> str:
        return generated_operator_id([s.trial_id for s in self.sources])

    @property
    def source_ids(self) -> list[str]:
        return sorted(s.trial_id for s in self.sources)

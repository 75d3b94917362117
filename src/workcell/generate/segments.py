"""A source trial cut at its recorded stage boundaries, each piece relative to its object.

The judge's stage is recorded with every frame (schema 5); wherever it changes, a segment
ends, with no annotation by hand. Each segment acts on one object
(:mod:`workcell.generate.references`) and is expressed relative to that object's pose at
its *anchor*: the segment's first frame, or, for an object still on the move there,
the frame it had rested for :data:`REST_S` (the motion before it is the operator waiting,
which is not replayed). Box transfer's two arms act on the same box at the same stages, so
both arms share one set of boundaries.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from workcell.generate.errors import GenerateError
from workcell.generate.planar import Planar
from workcell.generate.references import Reference
from workcell.generate.source import SourceTrial

REST_SPEED = 0.06
"""A box slower than this (m/s, on the floor plane) is at rest."""
REST_S = 0.5
"""How long a box must have rested before a segment that waits for it is anchored."""


@dataclass(frozen=True)
class Segment:
    """Frames ``start``..``end`` of a source trial (``end`` the frame its stage began)."""

    index: int
    start: int
    anchor: int
    """The first frame replayed, where the reference's pose is taken."""
    end: int
    end_stage: str
    reference: Reference
    pose: Planar
    """The reference object's pose at the anchor, in the source trial's world."""
    waits_for_rest: bool
    """Whether the attempt waits for its box to rest before the segment (the box was still
    moving at the segment's start in the source)."""

    def anchor_time(self, source: SourceTrial) -> float:
        """The source trial's time at the anchor."""
        return float(source.t[self.anchor])

    def as_dict(self) -> dict[str, object]:
        return {
            "index": self.index,
            "start_frame": self.start,
            "anchor_frame": self.anchor,
            "end_frame": self.end,
            "end_stage": self.end_stage,
            "reference": self.reference,
            "arms": ["l", "r"],
            "source_pose": self.pose.as_dict(),
        }


def segment(source: SourceTrial, references: Mapping[str, Reference]) -> tuple[Segment, ...]:
    """``source`` cut at each frame where its stage changes (the last frame ends the last
    segment)."""
    stages = source.stage
    unknown = sorted({stage for stage in stages if stage not in references})
    if unknown:
        raise GenerateError(
            f"source trial {source.trial_id}: its frames' stages {unknown} are not its "
            f"task's {tuple(references)} (a trial recorded before schema version 5 has none)"
        )
    bounds = [i for i in range(1, len(stages)) if stages[i] != stages[i - 1]]
    if not bounds or bounds[-1] != len(stages) - 1:
        bounds.append(len(stages) - 1)
    segments: list[Segment] = []
    start = 0
    for index, end in enumerate(bounds):
        reference = references[stages[end]]
        anchor, waits = _anchor(source, start, end, reference)
        segments.append(
            Segment(
                index,
                start,
                anchor,
                end,
                stages[end],
                reference,
                _pose(source, anchor, reference),
                waits,
            )
        )
        start = end
    return tuple(segments)


def _anchor(source: SourceTrial, start: int, end: int, reference: Reference) -> tuple[int, bool]:
    if reference == "goal":
        return start, False
    speed = source.box_pose[:, 3]
    if np.isfinite(speed[start]) and speed[start] < REST_SPEED:
        return start, False
    rest_since: float | None = None
    for i in range(start, end + 1):
        if np.isfinite(speed[i]) and speed[i] < REST_SPEED:
            rest_since = source.t[i] if rest_since is None else rest_since
            if source.t[i] - rest_since >= REST_S - 1e-9:
                return i, True
        else:
            rest_since = None
    raise GenerateError(
        f"source trial {source.trial_id}: its box never rested before stage "
        f"{source.stage[end]} (t = {source.t[end]:.2f} s); it cannot be replayed"
    )


def _pose(source: SourceTrial, frame: int, reference: Reference) -> Planar:
    if reference == "goal":
        return Planar(source.goal[0], source.goal[1], 0.0)
    x, y, yaw, _ = (float(v) for v in source.box_pose[frame])
    return Planar(x, y, yaw)

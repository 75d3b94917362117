"""A source trial cut at its recorded stage boundaries, each piece relative to its object.

The judge's stage is recorded with every frame (schema 5); wherever it changes, a segment
ends, with no annotation by hand. Each segment acts on one object
(:mod:`workcell.generate.references`) and is expressed relative to that object's pose at
its *anchor*: the segment's first frame, or, for an object still on the move there,
the frame it had rested for :data:`REST_S` (the motion before it is the operator waiting,
which is not replayed); a box a person's operator took while it still crept is anchored
as :data:`CREEP_SPEED` says. Box transfer's two arms act on the same box at the same stages, so
both arms share one set of boundaries.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from workcell.generate.errors import GenerateError
from workcell.generate.planar import Planar
from workcell.generate.source import SourceTrial
from workcell.tasks.task import Reference

REST_SPEED = 0.06
"""A box slower than this (m/s, on the floor plane) is at rest."""
REST_S = 0.5
"""How long a box must have rested before a segment that waits for it is anchored."""
CREEP_SPEED = 0.1
"""A box that never rested before the hands met it (a person's operator takes it as it
still creeps off the end of the belt, where the expert waits for it to stop) is anchored
where its average speed over :data:`REST_S` fell below this (half the belt's 0.2 m/s), and
moved from its pose where the segment ends: where the hands met it. The attempt waits for
its own box to rest as always, so the hands meet it where they met the source's."""


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
        if segments and segments[-1].reference == reference:
            # the same object on (a held box): replayed on from its start, unjoined, as
            # the operator does; not waited for, however the box moves in the hands
            anchor, waits, posed = start, False, start
        else:
            anchor, waits, posed = _anchor(source, start, end, reference)
        segments.append(
            Segment(
                index,
                start,
                anchor,
                end,
                stages[end],
                reference,
                _pose(source, posed, reference),
                waits,
            )
        )
        start = end
    return tuple(segments)


def _anchor(
    source: SourceTrial, start: int, end: int, reference: Reference
) -> tuple[int, bool, int]:
    """The anchor, whether the attempt waits for its box to rest, and the frame whose
    object pose the segment is moved from."""
    if reference == "goal":
        return start, False, start
    speed = source.box_pose[:, 3]
    if np.isfinite(speed[start]) and speed[start] < REST_SPEED:
        return start, False, start
    rest_since: float | None = None
    for i in range(start, end + 1):
        if np.isfinite(speed[i]) and speed[i] < REST_SPEED:
            rest_since = source.t[i] if rest_since is None else rest_since
            if source.t[i] - rest_since >= REST_S - 1e-9:
                return i, True, i
        else:
            rest_since = None
    crept = _slowed(source, start, end)
    if crept is not None:
        return crept, True, end
    raise GenerateError(
        f"source trial {source.trial_id}: its box never rested before stage "
        f"{source.stage[end]} (t = {source.t[end]:.2f} s); it cannot be replayed"
    )


def _slowed(source: SourceTrial, start: int, end: int) -> int | None:
    """The first frame by which the box had moved slower than :data:`CREEP_SPEED` on
    average over the :data:`REST_S` before it, or None."""
    xy, t = source.box_pose[:, :2], source.t
    for i in range(start, end + 1):
        j = int(np.searchsorted(t, t[i] - REST_S, side="right")) - 1
        if j < start or not (np.isfinite(xy[i]).all() and np.isfinite(xy[j]).all()):
            continue
        if float(np.linalg.norm(xy[i] - xy[j])) < CREEP_SPEED * float(t[i] - t[j]):
            return i
    return None


def _pose(source: SourceTrial, frame: int, reference: Reference) -> Planar:
    if reference == "goal":
        return Planar(source.goal[0], source.goal[1], 0.0)
    x, y, yaw, _ = (float(v) for v in source.box_pose[frame])
    return Planar(x, y, yaw)

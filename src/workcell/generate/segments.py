"""A source trial cut at its recorded stage boundaries, each piece relative to its object.

The judge's stage is recorded with every frame (schema 5); wherever it changes, a segment
ends, with no annotation by hand. A task that carries several boxes a trial (palletize)
cuts instead wherever the hands take a box or let go of one (the recorded ``attached``):
a segment ending where a box is taken acts on that box, one ending where it is let go of
on the goal site nearest to where it was set down. Each segment acts on one object
(:mod:`workcell.generate.references`) and is expressed relative to that object's pose at
its *anchor*: the segment's first frame, or, for an object still on the move there,
the frame it had rested for :data:`REST_S` (the motion before it is the operator waiting,
which is not replayed); a box a person's operator took while it still crept is anchored
as :data:`CREEP_SPEED` says. Box transfer's two arms act on the same box at the same stages, so
both arms share one set of boundaries.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from workcell.generate.errors import GenerateError
from workcell.generate.planar import Planar
from workcell.generate.source import NO_BOX, SourceTrial
from workcell.tasks.task import Reference, SegmentReferences

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


REACH_M = 1.0
"""A task cut where the hands take and let go of boxes (palletize): a segment acting on an
object begins where the base came within this distance (m, on the floor plan) of it."""


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
    box: int
    """The box the segment acts on or carries."""
    site: int
    """The goal site (an index of the task's :meth:`~workcell.tasks.Task.goal_sites`) a
    segment acting on the goal moves with (0 for one acting on a box)."""
    pose: Planar
    """The reference object's pose at the anchor, in the source trial's world."""
    waits_for_rest: bool
    """Whether the attempt waits for its box to rest before the segment (the box was still
    moving at the segment's start in the source)."""

    def acts_on_same_object(self, other: Segment | None) -> bool:
        """Whether ``other`` (the segment before) acts on the same object: this one then
        carries on with its motion, unjoined."""
        if other is None:
            return False
        return (self.reference, self.box, self.site) == (other.reference, other.box, other.site)

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
            "box": self.box,
            "site": self.site,
            "arms": ["l", "r"],
            "source_pose": self.pose.as_dict(),
        }


def segment(source: SourceTrial, references: SegmentReferences) -> tuple[Segment, ...]:
    """``source`` cut at each frame where its stage changes, or for :data:`BY_GRASP` where
    the hands take or let go of a box (the last frame ends the last segment)."""
    if isinstance(references, str):  # BY_GRASP
        return _by_grasp(source)
    stages = source.stage
    unknown = sorted({stage for stage in stages if stage not in references})
    if unknown:
        raise GenerateError(
            f"source trial {source.trial_id}: its frames' stages {unknown} are not its "
            f"task's {tuple(references)} (a trial recorded before schema version 5 has none)"
        )
    segments: list[Segment] = []
    start = 0
    for end in _change_points(stages):
        segments.append(_cut(source, segments, start, end, references[stages[end]], source.box, 0))
        start = end
    return tuple(segments)


def _by_grasp(source: SourceTrial) -> tuple[Segment, ...]:
    """Segments ending where the hands take a box (acting on it) or let go of it (acting
    on the goal site nearest where it was let go of), and at the last frame."""
    held = source.attached
    segments: list[Segment] = []
    start = 0
    for end in _change_points(held):
        if held[end] != NO_BOX and end != len(held) - 1:
            box, site = int(held[end]), 0
            start = _carry_on(source, segments, start, end, source.box_poses[box][:, :2])
            cut = _cut(source, segments, start, end, "box", box, site)
        else:
            carried = int(held[end - 1]) if held[end - 1] != NO_BOX else None
            if carried is None and segments:
                box, site = segments[-1].box, segments[-1].site
            elif carried is None:
                raise GenerateError(
                    f"source trial {source.trial_id}: its hands held nothing before its end"
                )
            else:
                box, site = carried, _nearest_site(source, carried, end)
            cut = _cut(source, segments, start, end, "goal", box, site)
        segments.append(cut)
        start = end
    return tuple(segments)


def _change_points(values: tuple[str, ...] | NDArray[np.int64]) -> list[int]:
    """The frames where ``values`` differs from the frame before, and the last frame."""
    points = [i for i in range(1, len(values)) if values[i] != values[i - 1]]
    if not points or points[-1] != len(values) - 1:
        points.append(len(values) - 1)
    return points


def _carry_on(
    source: SourceTrial,
    segments: list[Segment],
    start: int,
    end: int,
    spot: NDArray[np.float64],
) -> int:
    """Where a segment acting on an object at ``spot`` (x, y at each frame) begins: at
    ``start``, or, when the base was farther than :data:`REACH_M` from it there, at the
    first frame it came within reach; the frames before (leaving the last object and
    travelling) then carry on with the motion of the segment before, appended to
    ``segments``, so the join to the new object happens within reach of it and never
    while the hands are still at the object just let go of."""
    if not segments:
        return start
    distance = np.linalg.norm(source.base[start : end + 1, :2] - spot[start : end + 1], axis=1)
    near = np.flatnonzero(np.isfinite(distance) & (distance <= REACH_M))
    split = start + int(near[0]) if len(near) else start
    if start < split < end:
        previous = segments[-1]
        segments.append(
            _cut(source, segments, start, split, previous.reference, previous.box, previous.site)
        )
        return split
    return start


def _nearest_site(source: SourceTrial, box: int, frame: int) -> int:
    x, y = source.box_poses[box][frame, :2]
    distances = [math.hypot(site.x - x, site.y - y) for site in source.sites]
    return int(np.nanargmin(distances)) if np.isfinite(distances).any() else 0


def _cut(  # noqa: PLR0917 - a segment's parts
    source: SourceTrial,
    before: list[Segment],
    start: int,
    end: int,
    reference: Reference,
    box: int,
    site: int,
) -> Segment:
    """Frames ``start``..``end`` as a segment acting on ``reference`` (``box``, ``site``)."""
    if before and (before[-1].reference, before[-1].box, before[-1].site) == (reference, box, site):
        # the same object on (a held box): replayed on from its start, unjoined, as
        # the operator does; not waited for, however the box moves in the hands
        anchor, waits, posed = start, False, start
    else:
        anchor, waits, posed = _anchor(source, start, end, reference, box)
    return Segment(
        len(before),
        start,
        anchor,
        end,
        source.stage[end],
        reference,
        box,
        site,
        _pose(source, posed, reference, box, site),
        waits,
    )


def _anchor(
    source: SourceTrial, start: int, end: int, reference: Reference, box: int
) -> tuple[int, bool, int]:
    """The anchor, whether the attempt waits for its box to rest, and the frame whose
    object pose the segment is moved from."""
    if reference == "goal":
        return start, False, start
    speed = source.box_poses[box][:, 3]
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
    crept = _slowed(source, start, end, box)
    if crept is not None:
        return crept, True, end
    raise GenerateError(
        f"source trial {source.trial_id}: its box never rested before stage "
        f"{source.stage[end]} (t = {source.t[end]:.2f} s); it cannot be replayed"
    )


def _slowed(source: SourceTrial, start: int, end: int, box: int) -> int | None:
    """The first frame by which the box had moved slower than :data:`CREEP_SPEED` on
    average over the :data:`REST_S` before it, or None."""
    xy, t = source.box_poses[box][:, :2], source.t
    for i in range(start, end + 1):
        j = int(np.searchsorted(t, t[i] - REST_S, side="right")) - 1
        if j < start or not (np.isfinite(xy[i]).all() and np.isfinite(xy[j]).all()):
            continue
        if float(np.linalg.norm(xy[i] - xy[j])) < CREEP_SPEED * float(t[i] - t[j]):
            return i
    return None


def _pose(source: SourceTrial, frame: int, reference: Reference, box: int, site: int) -> Planar:
    if reference == "goal":
        goal = source.sites[site]
        return Planar(goal.x, goal.y, goal.yaw)
    x, y, yaw, _ = (float(v) for v in source.box_poses[box][frame])
    return Planar(x, y, yaw)

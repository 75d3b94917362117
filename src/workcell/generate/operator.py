"""The generator's operator: a source trial's segments replayed in a new world.

For each attempt it picks one source trial from the attempt's seed
(:meth:`GeneratedOperator.start_trial`), among those that share the attempt's
:meth:`~workcell.tasks.Task.source_key` where there are any (shelve: a source that put its box
on the asked board; sort: one whose boxes went to the same tables); then, segment by
segment, it takes the segment's object's pose in the new world (for an object still on the
move, once it has rested, replaying the source's frames before the segment's anchor
meanwhile), moves the segment with it (:class:`~workcell.generate.planar.Planar`), joins
the robot to the moved segment's first pose by a smooth blend
(:mod:`~workcell.generate.join`), and plays the moved segment: the base tracks the moved
path (the source's twist fed forward, its pose error fed back), the arms the moved targets,
grippers and head as recorded (a segment acting on a goal at another height is also moved
up or down by the difference). A segment acting on the same object as the one before it
carries on with its motion, unjoined (a held box's pose says nothing new). It reads the
world (the boxes, the zone, the base) and returns
:class:`~workcell.control.command.Command` values, like every operator; it never asks the
task's expert. What it did (each segment's motion and when it began) is
:attr:`GeneratedOperator.provenance`.
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from workcell.control.command import ArmCommand, BaseTwist, Command
from workcell.generate.join import MIN_JOIN_S, join_duration
from workcell.generate.motion import (
    MotionSample,
    blend,
    hands_in_base,
    sample,
    smoothstep,
    smoothstep_rate,
    widen,
)
from workcell.generate.plan import GenerationPlan
from workcell.generate.planar import Planar, wrap, yaw_of
from workcell.generate.segments import REST_S, REST_SPEED, Segment
from workcell.generate.source import SourceTrial
from workcell.sim.boxes import BoxState
from workcell.sim.world import World
from workcell.tasks.registry import load_task
from workcell.tasks.task import GoalSite

GAIN = (2.0, 2.5)
"""Base pose feedback: per second of linear and of yaw error."""
BOX_SYMMETRY = math.pi / 2
"""A box looks the same turned a quarter turn: a segment turns with it by the least angle."""


class Phase(enum.Enum):
    WAIT = "wait"
    JOIN = "join"
    PLAY = "play"
    HOLD = "hold"


@dataclass
class SegmentRun:
    """One segment as an attempt ran it: its motion and when it began (trial time)."""

    segment: Segment
    motion: Planar
    object_pose: Planar
    began_s: float
    widen_m: float
    """How far each hand was moved apart (a wider box than the source's)."""
    lift_m: float
    """How far both hands were moved up (a taller box; a goal at another height)."""
    approached_s: float = 0.0
    """How long the source's frames before the anchor were replayed while the segment's
    box was still on its way (:meth:`GeneratedOperator._approach`)."""

    def as_dict(self) -> dict[str, object]:
        return {
            **self.segment.as_dict(),
            "transform": self.motion.as_dict(),
            "widen_m": round(self.widen_m, 6),
            "lift_m": round(self.lift_m, 6),
            "approached_s": round(self.approached_s, 4),
            "object_pose": self.object_pose.as_dict(),
            "began_s": round(self.began_s, 4),
        }


@dataclass
class Provenance:
    """Where an attempt's motion came from."""

    source_trial_id: str = ""
    segments: list[SegmentRun] = field(default_factory=list)


class GeneratedOperator:
    """Replays the plan's source trials, one per attempt, moved into the attempt's world."""

    def __init__(self, plan: GenerationPlan) -> None:
        self.plan = plan
        self.task = load_task(plan.task)
        self.provenance = Provenance()
        self.start_trial(0)

    def start_trial(self, trial_seed: int) -> None:
        """A new attempt: its source trial is drawn from ``trial_seed`` when it first acts
        (where the attempt's goal stands is known then)."""
        self._rng = np.random.default_rng(trial_seed)
        self._picked = False
        self._source: SourceTrial = self.plan.sources[0]
        self._segments: tuple[Segment, ...] = self.plan.segments[0]
        self._sites: tuple[GoalSite, ...] = ()
        self.provenance = Provenance()
        self._index = 0
        self._phase = Phase.WAIT
        self._t0: float | None = None
        self._rest_since: float | None = None
        self._approach_began: float | None = None
        self._approach_from = Planar()
        self._motion = Planar()
        self._size_change = (0.0, 0.0)
        self._join_from: tuple[NDArray[np.float64], NDArray[np.float64]] | None = None
        self._join_to: MotionSample | None = None
        self._join_began = 0.0
        self._join_s = MIN_JOIN_S
        self._play_began = 0.0
        self._last = Command()
        self._last_hands: NDArray[np.float64] | None = None

    # --- the operator interface -------------------------------------------------------------

    def act(self, world: World) -> Command:
        if not self._picked:
            self._pick(world)
        if self._t0 is None:
            self._t0 = world.time
        if self._phase is Phase.WAIT:
            self._wait(world)
        if self._phase is Phase.JOIN:
            return self._join(world)
        if self._phase is Phase.PLAY:
            return self._play(world)
        if self._phase is Phase.WAIT:
            return self._approach(world)
        return self._hold(world)

    def _pick(self, world: World) -> None:
        """Draw the attempt's source trial, among those that share this attempt's
        :meth:`~workcell.tasks.Task.source_key` (all of them where none does)."""
        goal = self.task.goal(world.conditions.as_dict(), world.config)
        self._sites = self.task.goal_sites(goal)
        key = self.task.source_key(goal)
        sources = self.plan.sources
        alike = [i for i, s in enumerate(sources) if s.key == key]
        candidates = alike or list(range(len(sources)))
        pick = candidates[int(self._rng.integers(len(candidates)))]
        self._source, self._segments = sources[pick], self.plan.segments[pick]
        self.provenance = Provenance(self._source.trial_id)
        self._picked = True

    # --- phases ------------------------------------------------------------------------------

    def _wait(self, world: World) -> None:
        seg = self._segments[self._index]
        pose = self._object_pose(world, seg)
        if pose is None:
            return
        previous = self._segments[self._index - 1] if self._index else None
        continues = seg.acts_on_same_object(previous)
        if not continues and self.plan.retarget:
            self._motion = Planar.between(seg.pose, pose)
            half, lift = self._size_delta(world, seg.box)
            if seg.reference == "goal":
                lift += self._sites[seg.site].height - self._source.sites[seg.site].height
            self._size_change = (half, lift)
        approached = 0.0 if self._approach_began is None else world.time - self._approach_began
        self._approach_began = None
        self.provenance.segments.append(
            SegmentRun(
                seg,
                self._motion,
                pose,
                world.time - (self._t0 or 0.0),
                *self._size_change,
                approached,
            )
        )
        if continues:
            # the same object on: the motion goes on as it was (a held box moves with
            # the hands, so its pose now says nothing new)
            self._phase = Phase.PLAY
            self._play_began = world.time
            return
        target = self._moved(seg.anchor_time(self._source))
        current_base = world.base_pose
        hands = self._current_hands(world)
        self._join_from = (current_base, hands)
        self._join_to = target
        self._join_began = world.time
        self._join_s = join_duration(current_base, hands, target)
        self._phase = Phase.JOIN

    def _join(self, world: World) -> Command:
        assert self._join_from is not None and self._join_to is not None
        s = min(1.0, (world.time - self._join_began) / self._join_s)
        smooth = smoothstep(s)
        rate = smoothstep_rate(s) / self._join_s
        base_from, hands_from = self._join_from
        to = self._join_to
        delta = to.base - base_from
        delta[2] = wrap(float(delta[2]))
        reference = base_from + smooth * delta
        feed_world = rate * delta
        hands = blend(hands_from, to.hands, smooth)
        last = self._last
        feed = _to_base_twist(world.base_pose, feed_world)
        close = (last.close_left, last.close_right)
        command = self._command(
            world, MotionSample(reference, feed, hands, to.follow, close, to.head)
        )
        if s >= 1.0:
            self._phase = Phase.PLAY
            self._play_began = world.time
        return command

    def _play(self, world: World) -> Command:
        seg = self._segments[self._index]
        t = seg.anchor_time(self._source) + (world.time - self._play_began)
        end = float(self._source.t[seg.end])
        at = self._moved(min(t, end))
        command = self._command(world, at)
        if t >= end:
            self._index += 1
            self._phase = Phase.WAIT if self._index < len(self._segments) else Phase.HOLD
        return command

    def _approach(self, world: World) -> Command:
        """While the segment's box is still on its way: the source's frames before the
        anchor (its operator driving to where its own box came to rest, and waiting there),
        moved by a motion eased from the one the attempt carries on with (the first
        segment: the attempt's start against the source's) to none, since a box riding
        the belt comes to rest where the source's did, give or take the world's spread;
        held at the anchor's pose once played. The join to the box's actual pose follows
        when it has rested, from wherever this got to, a short way (without this, an
        attempt stood still at its start until its box had rested: 13 s of a box
        transfer trial, which a policy trained on such trials learns to do for ever)."""
        seg = self._segments[self._index]
        start_t, anchor_t = float(self._source.t[seg.start]), seg.anchor_time(self._source)
        if anchor_t <= start_t:
            return self._hold(world)
        if self._approach_began is None:
            self._approach_began = world.time
            self._approach_from = self._motion
            if self._index == 0 and self.plan.retarget:
                source_start = Planar.of(self._source.base[seg.start])
                self._approach_from = Planar.between(source_start, Planar.of(world.base_pose))
        s = min(1.0, (world.time - self._approach_began) / (anchor_t - start_t))
        motion = self._approach_from.scaled(1.0 - smoothstep(s))
        return self._command(world, self._sampled(start_t + s * (anchor_t - start_t), motion))

    def _hold(self, world: World) -> Command:
        last = self._last
        hands = self._last_hands
        if hands is None:
            return Command(head=last.head)
        local = hands_in_base(world.base_pose, hands)
        return Command(
            left=_arm(local[0], last.left.follow),
            right=_arm(local[1], last.right.follow),
            close_left=last.close_left,
            close_right=last.close_right,
            head=last.head,
        )

    # --- helpers -----------------------------------------------------------------------------

    def _object_pose(self, world: World, seg: Segment) -> Planar | None:
        """The segment's object's pose now, or None while a box it waits for still moves."""
        if seg.reference == "goal":
            site = self._sites[seg.site]
            return Planar(site.x, site.y, site.yaw)
        boxes = world.boxes
        slot = boxes.slots[seg.box]
        if slot.state is not BoxState.ACTIVE:
            self._rest_since = None
            return None
        if seg.waits_for_rest:
            speed = float(np.linalg.norm(world.data.qvel[slot.qvel : slot.qvel + 2]))
            if speed >= REST_SPEED:
                self._rest_since = None
                return None
            if self._rest_since is None:
                self._rest_since = world.time
            if world.time - self._rest_since < REST_S - 1e-9:
                return None
        x, y, _ = (float(v) for v in boxes.position(world.data, slot))
        yaw = yaw_of(boxes.quaternion(world.data, slot))
        turn = (yaw - seg.pose.yaw + BOX_SYMMETRY / 2) % BOX_SYMMETRY - BOX_SYMMETRY / 2
        return Planar(x, y, seg.pose.yaw + turn)

    def _size_delta(self, world: World, box: int) -> tuple[float, float]:
        """How much wider (per hand) and taller (half) this attempt's box ``box`` is than
        the source's: the hands move apart and up by as much."""
        source = self._source.box_sizes.get(box, (math.nan,) * 3)
        if not all(math.isfinite(v) for v in source):
            return (0.0, 0.0)
        size = world.boxes.size_of(world.boxes.slots[box])
        return ((size[1] - source[1]) / 2, (size[2] - source[2]) / 2)

    def _moved(self, t: float) -> MotionSample:
        return self._sampled(t, self._motion)

    def _sampled(self, t: float, motion: Planar) -> MotionSample:
        at = sample(self._source, t, motion)
        half, lift = self._size_change
        return MotionSample(
            at.base, at.twist, widen(at.hands, half, lift), at.follow, at.close, at.head
        )

    def _current_hands(self, world: World) -> NDArray[np.float64]:
        """Where the hands are asked to be now, in the world: the last command's targets,
        or the TCPs themselves where an arm was not following one."""
        last = self._last
        hands = np.empty((2, 7))
        for i, (side, arm) in enumerate((("l", last.left), ("r", last.right))):
            if arm.follow and self._last_hands is not None:
                hands[i] = self._last_hands[i]
            else:
                position, quaternion = world.tcp_pose(side)
                hands[i, :3], hands[i, 3:] = position, quaternion
        return hands

    def _command(self, world: World, at: MotionSample) -> Command:
        """Track ``at``: its base pose (its twist fed forward, the pose error fed back),
        its hands in the world, its grippers and head."""
        reference, feed, hands = at.base, at.twist, at.hands
        pose = world.base_pose
        error = _to_base_twist(pose, reference[:2] - pose[:2])
        yaw_error = wrap(float(reference[2] - pose[2]))
        robot = world.config.robot
        linear = feed[:2] + GAIN[0] * error[:2]
        speed = float(np.linalg.norm(linear))
        if speed > robot.max_linear_speed:
            linear *= robot.max_linear_speed / speed
        wz = float(np.clip(feed[2] + GAIN[1] * yaw_error, -robot.max_yaw_rate, robot.max_yaw_rate))
        local = hands_in_base(pose, hands)
        command = Command(
            base=BaseTwist(float(linear[0]), float(linear[1]), wz),
            left=_arm(local[0], at.follow[0]),
            right=_arm(local[1], at.follow[1]),
            close_left=float(np.clip(at.close[0], 0.0, 1.0)),
            close_right=float(np.clip(at.close[1], 0.0, 1.0)),
            head=at.head,
        )
        self._last = command
        self._last_hands = hands
        return command


def _arm(pose: NDArray[np.float64], follow: bool) -> ArmCommand:
    """Follow ``pose`` (base frame); an arm the source did not have following (a person's
    released clutch), or without a target, holds where it is."""
    if not (follow and np.isfinite(pose).all()):
        return ArmCommand()
    q = pose[3:] / np.linalg.norm(pose[3:])
    return ArmCommand(
        (float(pose[0]), float(pose[1]), float(pose[2])),
        (float(q[0]), float(q[1]), float(q[2]), float(q[3])),
        True,
    )


def _to_base_twist(pose: NDArray[np.float64], world_xy: NDArray[np.float64]) -> NDArray[np.float64]:
    """A world vector (x, y[, yaw]) in the frame of a base at ``pose``."""
    c, s = math.cos(float(pose[2])), math.sin(float(pose[2]))
    out = np.zeros(3)
    out[0] = c * world_xy[0] + s * world_xy[1]
    out[1] = -s * world_xy[0] + c * world_xy[1]
    if len(world_xy) > 2:
        out[2] = world_xy[2]
    return out

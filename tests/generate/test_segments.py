"""Cutting a source trial at its recorded stage changes (or, for a task carrying several
boxes, where the hands take and let go of each), each segment anchored on its object: a box
still riding the belt is waited for until it has rested."""

from __future__ import annotations

import numpy as np
import pytest
from examples.lift_box.task import LiftBox

from workcell.generate.errors import GenerateError
from workcell.generate.references import references_for
from workcell.generate.segments import REACH_M, segment
from workcell.generate.source import NO_BOX, SourceTrial
from workcell.tasks.box_transfer.task import BoxTransfer
from workcell.tasks.palletize.task import Palletize
from workcell.tasks.sort.task import Sort
from workcell.tasks.task import BY_GRASP, GoalSite

RATE_HZ = 20
REFERENCES = references_for(BoxTransfer())


def source(stages: list[str]) -> SourceTrial:
    """A trial of ``len(stages)`` frames at 20 Hz whose box rides the belt at 0.2 m/s for
    its first 40 frames and rests after."""
    n = len(stages)
    t = np.arange(n) / RATE_HZ
    box = np.zeros((n, 4))
    box[:, 0] = -1.0 + 0.2 * np.minimum(t, 2.0)
    box[:, 1] = -0.02
    box[:, 2] = 0.05
    box[:, 3] = np.where(t <= 2.0, 0.2, 0.0)
    return SourceTrial(
        trial_id="t",
        operator_id="expert",
        t=t,
        base=np.zeros((n, 3)),
        twist=np.zeros((n, 3)),
        targets=np.zeros((n, 2, 7)),
        follow=np.ones((n, 2), dtype=bool),
        close=np.zeros((n, 2)),
        head=np.zeros((n, 2)),
        stage=tuple(stages),
        box=0,
        attached=np.full(n, NO_BOX),
        box_poses={0: box},
        sites=(GoalSite(1.6, 1.9),),
        key=(),
        box_sizes={0: (0.3, 0.3, 0.3)},
    )


def test_segments_end_where_the_stage_changes_and_act_on_their_object() -> None:
    stages = ["none"] * 80 + ["grasped"] * 5 + ["lifted"] * 30 + ["over_zone"] * 20
    stages.append("delivered")
    segments = segment(source(stages), REFERENCES)
    assert [(s.start, s.end, s.end_stage) for s in segments] == [
        (0, 80, "grasped"),
        (80, 85, "lifted"),
        (85, 115, "over_zone"),
        (115, 135, "delivered"),
    ]
    assert [s.reference for s in segments] == ["box", "box", "goal", "goal"]
    first = segments[0]
    # the box rests from frame 41 (t = 2.05 s); anchored once it has rested 0.5 s
    assert first.waits_for_rest and first.anchor == 51
    assert first.pose.x == pytest.approx(-0.6) and first.pose.yaw == pytest.approx(0.05)
    assert not segments[1].waits_for_rest and segments[1].anchor == 80
    assert (segments[2].pose.x, segments[2].pose.y) == (1.6, 1.9)


def test_a_trial_without_its_tasks_stages_is_refused() -> None:
    with pytest.raises(GenerateError, match="recorded before schema version 5"):
        segment(source(["None"] * 10), REFERENCES)
    with pytest.raises(GenerateError, match="lift_box: the task declares no segment ref"):
        references_for(LiftBox())
    assert references_for(Palletize()) == references_for(Sort()) == BY_GRASP

    class Shortened(BoxTransfer):
        stages = ("none", "touched", "grasped", "lifted", "delivered")

    with pytest.raises(GenerateError, match="not its stages none > touched > grasped > lifted > d"):
        references_for(Shortened())


def creeping(speeds: np.ndarray) -> SourceTrial:
    """:func:`source` whose box, after the belt, slides on at ``speeds`` (one per frame
    from frame 41), its x integrated from them, as recorded frame to frame."""
    stages = ["none"] * 100 + ["grasped"] * 5
    trial = source(stages)
    box = trial.box_pose.copy()
    box[41:, 3] = speeds[: len(box) - 41]
    box[41:, 0] = box[40, 0] + np.cumsum(box[41:, 3]) / RATE_HZ
    return SourceTrial(**{**trial.__dict__, "operator_id": "teleop", "box_poses": {0: box}})


def test_a_box_taken_while_it_still_creeps_is_moved_from_where_the_hands_met_it() -> None:
    # a person's operator (bench/teleop_sources.py) takes the box as it creeps off the belt
    # at a few cm/s, its frame-to-frame speed above and below the rest speed by turns
    speeds = np.where(np.arange(64) % 2 == 0, 0.07, 0.04)
    trial = creeping(speeds)
    (first, _) = segment(trial, REFERENCES)
    # never at rest for 0.5 s; below 0.1 m/s on average over frames 37 to 47 (3 frames at
    # 0.2 m/s, 7 at 0.055): replayed from there, moved from the box's pose at the grasp
    assert first.waits_for_rest and first.anchor == 47
    assert first.pose.x == pytest.approx(trial.box_pose[100, 0])


def test_a_box_that_never_slows_down_is_refused() -> None:
    with pytest.raises(GenerateError, match="never rested before stage grasped"):
        segment(creeping(np.full(64, 0.12)), REFERENCES)


def test_a_box_moving_in_the_hands_from_the_grasp_on_is_not_waited_for() -> None:
    # a person's squeeze moves the box as it closes: the segment on the same box after
    # the grasp carries on from its start, as the operator replays it (unjoined)
    stages = ["none"] * 80 + ["grasped"] * 5 + ["lifted"] * 30 + ["over_zone"] * 5
    trial = source(stages)
    box = trial.box_pose.copy()
    box[80:, 3] = 0.3
    moving = SourceTrial(**{**trial.__dict__, "box_poses": {0: box}})
    first, second, *_ = segment(moving, REFERENCES)
    assert first.waits_for_rest and first.anchor == 51
    assert (second.start, second.anchor, second.waits_for_rest) == (80, 80, False)


def two_carries() -> SourceTrial:
    """Two boxes carried to two goal sites, 1 s a frame apart: box 0 waits at (0, 0) and is
    held in frames 20-39, box 1 at (0, 1) in frames 70-89; from frame 40 the base stands
    at y = 1 and drives from x = 4 back toward box 1 (x falling 0.2 m a frame to 0.5)."""
    n = 100
    attached = np.full(n, NO_BOX)
    attached[20:40], attached[70:90] = 0, 1
    base = np.zeros((n, 3))
    base[:, 0] = np.clip(4.0 - 0.2 * (np.arange(n) - 40), 0.5, 4.0)
    base[:20, 0] = 0.5
    base[40:, 1] = 1.0
    poses = {b: np.zeros((n, 4)) for b in (0, 1)}
    poses[1][:, 1] = 1.0
    poses[0][40:, :2] = (4.2, 0.3)  # let go of beside the first site
    poses[1][90:, :2] = (4.2, -0.9)  # and beside the second
    trial = source(["none"] * 20 + ["grasped"] * 20 + ["placed_1"] * 50 + ["placed_2"] * 10)
    fields = {**trial.__dict__, "base": base, "attached": attached, "box_poses": poses}
    return SourceTrial(**{**fields, "sites": (GoalSite(4.2, -1.0), GoalSite(4.2, 0.2))})


def test_a_task_of_several_boxes_is_cut_where_the_hands_take_and_let_go_of_each() -> None:
    segments = segment(two_carries(), BY_GRASP)
    assert [(s.start, s.end, s.reference, s.box, s.site) for s in segments] == [
        (0, 20, "box", 0, 0),  # to the grasp of box 0
        (20, 40, "goal", 0, 1),  # carried to the site nearest where it was let go of
        (40, 55, "goal", 0, 1),  # travelling back: the carry's motion goes on ...
        (55, 70, "box", 1, 0),  # ... until the base is within REACH_M of box 1
        (70, 90, "goal", 1, 0),
        (90, 99, "goal", 1, 0),  # after the last let-go: on with the same motion
    ]
    assert two_carries().base[55, 0] <= REACH_M < two_carries().base[54, 0]
    travel, reach = segments[2], segments[3]
    assert travel.acts_on_same_object(segments[1]) and not reach.acts_on_same_object(travel)
    assert (reach.pose.x, reach.pose.y) == (0.0, 1.0)
    assert (segments[4].pose.x, segments[4].pose.y) == (4.2, -1.0)

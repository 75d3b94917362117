"""Cutting a source trial at its recorded stage changes, each segment anchored on its
object: a box still riding the belt is waited for until it has rested."""

from __future__ import annotations

import numpy as np
import pytest

from workcell.generate.errors import GenerateError
from workcell.generate.references import references_for
from workcell.generate.segments import segment
from workcell.generate.source import SourceTrial
from workcell.tasks.box_transfer.task import BoxTransfer
from workcell.tasks.palletize.task import Palletize

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
        box_pose=box,
        goal=(1.6, 1.9, 0.0),
        box_size=(0.3, 0.3, 0.3),
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
    with pytest.raises(GenerateError, match="palletize: the task declares no segment ref"):
        references_for(Palletize())

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
    return SourceTrial(**{**trial.__dict__, "operator_id": "teleop", "box_pose": box})


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
    moving = SourceTrial(**{**trial.__dict__, "box_pose": box})
    first, second, *_ = segment(moving, REFERENCES)
    assert first.waits_for_rest and first.anchor == 51
    assert (second.start, second.anchor, second.waits_for_rest) == (80, 80, False)

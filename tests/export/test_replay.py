"""Restoring recorded states reproduces the recorded poses; renders come from them."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from tests.export.stores import Stores
from workcell.export.errors import ReplayMismatchError, UnknownTrialError
from workcell.export.options import ImageSize
from workcell.export.replay import TCP_TOLERANCE_M, replay_check
from workcell.export.replay_world import ReplayWorld
from workcell.export.restore import RecordedStates
from workcell.export.source import session_config
from workcell.record.store import Store


def test_every_recorded_trial_replays_within_tolerance(recorded: Stores) -> None:
    with Store.open(recorded.mixed, writer=False) as store:
        errors = [replay_check(store, trial.trial_id) for trial in store.trials()]
    assert len(errors) == 4
    assert max(errors) <= TCP_TOLERANCE_M


def test_changed_joints_fail_the_check(recorded: Stores) -> None:
    with Store.open(recorded.short, writer=False) as store:
        trial = store.trials()[0]
        config = session_config(store.sessions()[0])
        states = RecordedStates.from_frames(store.frames(trial.trial_id))
    world = ReplayWorld(config)
    assert world.check(states, trial.trial_id).position_m <= TCP_TOLERANCE_M
    bent = dataclasses.replace(states, joints=states.joints + 0.01)
    with pytest.raises(ReplayMismatchError, match=f"trial {trial.trial_id}: restoring"):
        world.check(bent, trial.trial_id)


def test_restored_frames_render_what_the_robot_saw(recorded: Stores) -> None:
    with Store.open(recorded.short, writer=False) as store:
        trial = store.trials()[0]
        config = session_config(store.sessions()[0])
        states = RecordedStates.from_frames(store.frames(trial.trial_id))
    world = ReplayWorld(config, ImageSize(64, 48))
    try:
        images = [frame["head_cam"] for frame in world.images(states, ["head_cam"])]
    finally:
        world.close()
    assert len(images) == len(states)
    assert images[0].shape == (48, 64, 3)
    assert all(image.std() > 1.0 for image in images[:: len(images) // 4])
    assert not np.array_equal(images[0], images[-1])  # the robot moved


def test_unknown_trial_is_one_clear_error(recorded: Stores) -> None:
    with (
        Store.open(recorded.short, writer=False) as store,
        pytest.raises(UnknownTrialError, match="no trial nope"),
    ):
        replay_check(store, "nope")

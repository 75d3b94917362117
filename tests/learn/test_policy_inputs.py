"""A policy's inputs checked against the session (src/workcell/learn/features.py): a policy
trained before the robot-relative environment features still drives, reading the leading
world-frame numbers it was trained on; any other size is refused with both sizes named."""

from __future__ import annotations

from pathlib import Path

import pytest
from lerobot.configs.types import FeatureType, PolicyFeature
from lerobot.policies.act.configuration_act import ACTConfig

from workcell.export.boxes import environment_names, world_environment_names
from workcell.export.features import (
    ACTION_KEY,
    ACTION_NAMES,
    ENVIRONMENT_KEY,
    STATE_KEY,
    STATE_NAMES,
)
from workcell.learn.checkpoint import PolicyCheckpoint
from workcell.learn.errors import LearnError
from workcell.learn.features import policy_inputs

GOAL = ("goal_x", "goal_y")
FULL, WORLD = environment_names(4, GOAL), world_environment_names(4, GOAL)


def _config(environment: int) -> ACTConfig:
    return ACTConfig(
        input_features={
            STATE_KEY: PolicyFeature(FeatureType.STATE, (len(STATE_NAMES),)),
            ENVIRONMENT_KEY: PolicyFeature(FeatureType.ENV, (environment,)),
        },
        output_features={ACTION_KEY: PolicyFeature(FeatureType.ACTION, (len(ACTION_NAMES),))},
    )


CHECKPOINT = PolicyCheckpoint(Path("act/pretrained_model"), "act", "0" * 64, "act")


def test_a_policy_reads_as_many_environment_numbers_as_it_was_trained_on() -> None:
    assert FULL[: len(WORLD)] == WORLD and len(FULL) > len(WORLD)
    assert policy_inputs(CHECKPOINT, _config(len(FULL)), FULL, WORLD).environment_size == len(FULL)
    older = policy_inputs(CHECKPOINT, _config(len(WORLD)), FULL, WORLD)
    assert older.environment_size == len(WORLD)


def test_another_size_is_refused_naming_what_the_session_has() -> None:
    with pytest.raises(
        LearnError,
        match=rf"of shape \(7,\), where this session has \({len(FULL)},\) or \({len(WORLD)},\)",
    ):
        policy_inputs(CHECKPOINT, _config(7), FULL, WORLD)

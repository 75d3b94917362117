"""What a policy reads and writes, checked against what a Workcell session provides.

A policy trained on a Workcell export reads some of ``observation.state``,
``observation.environment_state`` and ``observation.images.<camera>`` and writes
``action``, with the shapes the export gave them. A policy whose features do not fit the
session it is asked to drive (another robot's dataset, a world with more boxes) is refused
before the session starts, with what it expects and what the session has.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from workcell.export.features import (
    ACTION_KEY,
    ACTION_NAMES,
    ENVIRONMENT_KEY,
    IMAGE_PREFIX,
    STATE_KEY,
    STATE_NAMES,
)
from workcell.export.options import ROBOT_CAMERAS, ImageSize
from workcell.learn.checkpoint import PolicyCheckpoint
from workcell.learn.errors import LearnError


@dataclass(frozen=True)
class PolicyInputs:
    """The cameras a policy looks through (and their image size), besides the vectors."""

    cameras: tuple[str, ...]
    image_size: ImageSize | None
    environment_size: int
    """How many leading numbers of ``observation.environment_state`` the policy reads: all
    of them, or only the world-frame boxes and goal of a policy trained before the relative
    features (:mod:`workcell.export.relative`) were exported."""


def policy_inputs(
    checkpoint: PolicyCheckpoint,
    config: Any,
    environment: Sequence[str],
    world_environment: Sequence[str],
) -> PolicyInputs:
    """Check the policy ``config`` (a LeRobot ``PreTrainedConfig``) against a session whose
    ``observation.environment_state`` has the names ``environment`` (every box of its pool,
    then its task's goal, then both relative to the robot:
    :func:`workcell.export.boxes.environment_names`), of which a policy trained on an older
    export reads the leading ``world_environment``; its cameras and image size."""
    inputs: Mapping[str, Any] = config.input_features or {}
    outputs: Mapping[str, Any] = config.output_features or {}
    vectors = {
        STATE_KEY: ((len(STATE_NAMES),),),
        ENVIRONMENT_KEY: ((len(environment),), (len(world_environment),)),
    }
    problems = []
    cameras: list[str] = []
    sizes: set[tuple[int, int]] = set()
    environment_size = len(environment)
    for key, feature in inputs.items():
        shape = tuple(int(v) for v in feature.shape)
        if key in vectors:
            if shape not in vectors[key]:
                allowed = " or ".join(str(v) for v in vectors[key])
                problems.append(f"{key} of shape {shape}, where this session has {allowed}")
            elif key == ENVIRONMENT_KEY:
                environment_size = shape[0]
        elif key.startswith(IMAGE_PREFIX) and key[len(IMAGE_PREFIX) :] in ROBOT_CAMERAS:
            if len(shape) != 3 or shape[0] != 3:
                problems.append(f"{key} of shape {shape}: images are (3, height, width)")
                continue
            cameras.append(key[len(IMAGE_PREFIX) :])
            sizes.add((shape[2], shape[1]))
        else:
            problems.append(f"{key}, which a Workcell session does not provide")
    action = outputs.get(ACTION_KEY)
    if action is None or tuple(int(v) for v in action.shape) != (len(ACTION_NAMES),):
        written = None if action is None else tuple(action.shape)
        problems.append(
            f"{ACTION_KEY} of shape {written}, where Workcell's is ({len(ACTION_NAMES)},)"
        )
    if len(sizes) > 1:
        problems.append(f"images of several sizes {sorted(sizes)}; one size for every camera")
    if problems:
        raise LearnError(
            f"policy {checkpoint.operator_id} ({checkpoint.path}) does not fit this session: "
            f"it uses {'; '.join(problems)}"
        )
    size = None
    if sizes:
        width, height = sizes.pop()
        size = ImageSize(width, height)
    return PolicyInputs(tuple(cameras), size, environment_size)

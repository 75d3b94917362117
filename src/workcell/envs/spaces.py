"""Observation and action spaces: the dataset features, with the controller's limits.

Observations follow LeRobot's gym convention (:mod:`workcell.envs.observation`):
``agent_pos`` and ``environment_state`` (float32, unbounded) and, with cameras,
``pixels`` (uint8 images). Actions are the ``action`` feature (float32); its bounds are
what the controller would apply anyway (base speed and turn rate, gripper 0..1, head joint
ranges) or generous reach limits for the TCP targets, so clipping an action to the space
does not change what the robot does with it.
"""

from __future__ import annotations

import numpy as np
from gymnasium import spaces

from workcell.envs.config import BoxTransferConfig
from workcell.envs.observation import AGENT_POS, ENVIRONMENT_STATE, PIXELS
from workcell.export.boxes import environment_names
from workcell.export.features import ACTION_NAMES, STATE_NAMES
from workcell.sim.world import World
from workcell.tasks.registry import load_task

TARGET_REACH_M = 2.0
"""TCP targets (base frame) lie within this distance of the base centre in x and y."""
TARGET_HEIGHT_M = (0.0, 2.5)


def observation_space(config: BoxTransferConfig) -> spaces.Dict:
    def unbounded(size: int) -> spaces.Box:
        return spaces.Box(-np.inf, np.inf, shape=(size,), dtype=np.float32)

    pool_size = config.session.world.feeder.pool_size
    goal_names = load_task(config.session.task.kind).goal_names
    observation: dict[str, spaces.Space[object]] = {
        AGENT_POS: unbounded(len(STATE_NAMES)),
        ENVIRONMENT_STATE: unbounded(len(environment_names(pool_size, goal_names))),
    }
    if config.cameras:
        size = config.camera_size
        image = spaces.Box(0, 255, shape=(size.height, size.width, 3), dtype=np.uint8)
        observation[PIXELS] = spaces.Dict({camera: image for camera in config.cameras})
    return spaces.Dict(observation)


def action_bounds(config: BoxTransferConfig, world: World) -> dict[str, tuple[float, float]]:
    """Lower and upper bound of every action dimension, by name."""
    robot = config.session.world.robot
    model = world.model
    bounds: dict[str, tuple[float, float]] = {
        "cmd_vx": (-robot.max_linear_speed, robot.max_linear_speed),
        "cmd_vy": (-robot.max_linear_speed, robot.max_linear_speed),
        "cmd_wz": (-robot.max_yaw_rate, robot.max_yaw_rate),
    }
    for side in ("l", "r"):
        prefix = f"target_{side}"
        bounds[f"{prefix}_x"] = bounds[f"{prefix}_y"] = (-TARGET_REACH_M, TARGET_REACH_M)
        bounds[f"{prefix}_z"] = TARGET_HEIGHT_M
        for part in ("qw", "qx", "qy", "qz"):
            bounds[f"{prefix}_{part}"] = (-1.0, 1.0)
        bounds[f"follow_{side}"] = bounds[f"gripper_cmd_{side}"] = (0.0, 1.0)
    for name, joint in (("head_cmd_pan", "head_pan"), ("head_cmd_tilt", "head_tilt")):
        low, high = model.jnt_range[model.joint(joint).id]
        bounds[name] = (float(low), float(high))
    return bounds


def action_space(config: BoxTransferConfig, world: World) -> spaces.Box:
    bounds = action_bounds(config, world)
    low = np.array([bounds[name][0] for name in ACTION_NAMES], dtype=np.float32)
    high = np.array([bounds[name][1] for name in ACTION_NAMES], dtype=np.float32)
    return spaces.Box(low, high, dtype=np.float32)

"""Compose the compiled models: the full world, and the robot-only model the IK solves on."""

from __future__ import annotations

from typing import Protocol

import mujoco

from workcell.sim.arena import build_arena
from workcell.sim.config import WorldConfig
from workcell.sim.robot import build_robot
from workcell.sim.spec_utils import ROBOT_CONAFFINITY, ROBOT_CONTYPE, set_env_collision

OBSTACLE_PROXY = "obstacle_proxy"
"""Mocap body of the IK model standing in for the fixture the arms keep clear of
(:attr:`WorldConfig.arm_obstacle`), in the base frame."""
OBSTACLE_PROXY_GEOM = "obstacle_proxy_geom"


class SceneBuilder(Protocol):
    """What a task adds to the shared factory's model (:class:`workcell.sim.world.TaskScene`)."""

    def build(self, spec: mujoco.MjSpec, config: WorldConfig) -> None:
        """Add the task's elements (pallets, shelves, tables, marks) to ``spec``."""


def world_spec(config: WorldConfig, task: SceneBuilder | None = None) -> mujoco.MjSpec:
    """The full scene's spec: the arena, then ``task``'s elements, then the robot."""
    spec = mujoco.MjSpec()
    spec.modelname = "workcell"
    spec.compiler.degree = False
    opt = spec.option
    opt.timestep = config.timestep
    opt.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    opt.cone = mujoco.mjtCone.mjCONE_ELLIPTIC
    opt.impratio = 10.0
    spec.visual.global_.offwidth = 1280
    spec.visual.global_.offheight = 720
    build_arena(spec, config)
    if task is not None:
        task.build(spec, config)
    build_robot(spec, mobile=True)
    return spec


def build_world_model(config: WorldConfig, task: SceneBuilder | None = None) -> mujoco.MjModel:
    """The full scene: arena, boxes, ``task``'s elements and the mobile robot with its
    actuators."""
    return world_spec(config, task).compile()


def build_ik_model(config: WorldConfig) -> mujoco.MjModel:
    """The robot on a fixed base at the origin, plus a mocap proxy of the fixture the arms
    keep clear of."""
    spec = mujoco.MjSpec()
    spec.modelname = "workcell_ik"
    spec.compiler.degree = False
    build_robot(spec, mobile=False)
    # In the world the robot's geoms never touch each other (arm-arm clearance is the IK's
    # job); here they must pass MuJoCo's contype/conaffinity test with each other, or the
    # IK's collision limit (mink) leaves every arm-arm pair out.
    for geom in spec.geoms:
        if geom.contype == ROBOT_CONTYPE:
            geom.conaffinity = ROBOT_CONAFFINITY | ROBOT_CONTYPE
    _center, half_size = config.arm_obstacle
    proxy = spec.worldbody.add_body(name=OBSTACLE_PROXY, mocap=True, pos=[0, 0, -10])
    geom = proxy.add_geom(
        name=OBSTACLE_PROXY_GEOM, type=mujoco.mjtGeom.mjGEOM_BOX, size=list(half_size)
    )
    set_env_collision(geom)
    return spec.compile()

"""The mobile bimanual robot, built with MjSpec from primitives.

Holonomic base (slide x, slide y, hinge yaw), a vertical spine, a pan/tilt head with a
camera, and two 7-DoF arms with Franka Panda kinematics (see :mod:`workcell.sim.panda`)
ending in parallel grippers with palm pads. The same builder makes the simulated robot
(``mobile=True``) and the fixed-base robot-only model the IK solves on.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import mujoco
import numpy as np

from workcell.sim import panda
from workcell.sim.joints import (
    BASE_JOINTS,
    FINGER_JOINTS,
    HEAD_JOINTS,
    SIDES,
    SPINE_JOINT,
    arm_joint_names,
)
from workcell.sim.looks import add_decor, add_looks
from workcell.sim.spec_utils import (
    Quat,
    Vec3,
    quat_axis_angle,
    rotate,
    set_robot_collision,
    set_visual_only,
)

BOX = mujoco.mjtGeom.mjGEOM_BOX
CAPSULE = mujoco.mjtGeom.mjGEOM_CAPSULE
CYLINDER = mujoco.mjtGeom.mjGEOM_CYLINDER
SPHERE = mujoco.mjtGeom.mjGEOM_SPHERE
HINGE = mujoco.mjtJoint.mjJNT_HINGE
SLIDE = mujoco.mjtJoint.mjJNT_SLIDE

BODY_RGBA = (0.93, 0.93, 0.95, 1.0)
ACCENT_RGBA = (0.16, 0.32, 0.62, 1.0)
DARK_RGBA = (0.18, 0.18, 0.2, 1.0)
PAD_RGBA = (0.15, 0.55, 0.25, 1.0)
SIGNAL_RGBA = (0.25, 0.8, 1.0, 1.0)


@dataclass(frozen=True)
class RobotGeometry:
    """Dimensions of the robot body (metres); fixed, not a user parameter."""

    base_half: Vec3 = (0.32, 0.27, 0.13)
    base_clearance: float = 0.06
    torso_z: float = 0.32
    spine_range: tuple[float, float] = (0.0, 0.35)
    shoulder_z: float = 0.5
    shoulder_x: float = 0.06
    shoulder_y: float = 0.2
    head_z: float = 0.72
    pad_half: Vec3 = (0.05, 0.06, 0.0125)
    pad_center_z: float = 0.125
    finger_open: float = 0.04


GEOMETRY = RobotGeometry()
TCP_OFFSET_Z = GEOMETRY.pad_center_z + GEOMETRY.pad_half[2]
"""The TCP sits at the centre of the palm pad's outer face, z along the approach."""


def build_robot(spec: mujoco.MjSpec, *, mobile: bool) -> None:
    """Add the robot to ``spec``'s world body, with actuators when ``mobile``."""
    g = GEOMETRY
    add_looks(spec, "robot_shell", "rubber", "signal")
    base = spec.worldbody.add_body(name="base")
    if mobile:
        base.add_joint(name=BASE_JOINTS[0], type=SLIDE, axis=[1, 0, 0], armature=1.0)
        base.add_joint(name=BASE_JOINTS[1], type=SLIDE, axis=[0, 1, 0], armature=1.0)
        base.add_joint(name=BASE_JOINTS[2], type=HINGE, axis=[0, 0, 1], armature=1.0)
    chassis = base.add_geom(
        name="chassis",
        type=BOX,
        size=list(g.base_half),
        pos=[0, 0, g.base_clearance + g.base_half[2]],
        rgba=list(BODY_RGBA),
        material="robot_shell",
        mass=45.0,
    )
    set_robot_collision(chassis)
    bumper = base.add_geom(
        name="bumper",
        type=BOX,
        size=[g.base_half[0] + 0.01, g.base_half[1] + 0.01, 0.03],
        pos=[0, 0, g.base_clearance + 0.04],
        rgba=list(DARK_RGBA),
        material="rubber",
        mass=1.0,
    )
    set_visual_only(bumper)
    for i, (wx, wy) in enumerate([(1, 1), (1, -1), (-1, 1), (-1, -1)]):
        wheel = base.add_geom(
            name=f"wheel_{i}",
            type=CYLINDER,
            size=[0.06, 0.025, 0],
            pos=[wx * (g.base_half[0] - 0.08), wy * (g.base_half[1] + 0.005), 0.06],
            quat=list(quat_axis_angle((1, 0, 0), math.pi / 2)),
            rgba=list(DARK_RGBA),
            material="rubber",
            mass=0.5,
        )
        set_visual_only(wheel)

    _add_base_decor(base)
    torso = base.add_body(name="torso", pos=[0, 0, g.torso_z], gravcomp=1.0)
    torso.add_joint(
        name=SPINE_JOINT,
        type=SLIDE,
        axis=[0, 0, 1],
        range=list(g.spine_range),
        limited=mujoco.mjtLimited.mjLIMITED_TRUE,
        armature=1.0,
        damping=50.0,
    )
    column = torso.add_geom(
        name="column",
        type=BOX,
        size=[0.09, 0.12, 0.24],
        pos=[-0.05, 0, 0.24],
        rgba=list(BODY_RGBA),
        material="robot_shell",
        mass=8.0,
    )
    set_robot_collision(column)
    shoulders = torso.add_geom(
        name="shoulder_bar",
        type=BOX,
        size=[0.07, g.shoulder_y + 0.05, 0.035],
        pos=[g.shoulder_x - 0.03, 0, g.shoulder_z - 0.035],
        rgba=list(ACCENT_RGBA),
        material="robot_shell",
        mass=3.0,
    )
    set_robot_collision(shoulders)
    _add_head(torso)
    for side in SIDES:
        sign = 1.0 if side == "l" else -1.0
        _add_arm(torso, side, (g.shoulder_x, sign * g.shoulder_y, g.shoulder_z))
    if mobile:
        _add_actuators(spec)


def _add_base_decor(base: mujoco.MjsBody) -> None:
    """A lit status strip around the chassis and a lidar on its nose."""
    g = GEOMETRY
    top = g.base_clearance + 2 * g.base_half[2]
    add_decor(
        base,
        "status_strip",
        BOX,
        [g.base_half[0] + 0.003, g.base_half[1] + 0.003, 0.008],
        rgba=SIGNAL_RGBA,
        material="signal",
        pos=[0, 0, top - 0.03],
    )
    add_decor(
        base,
        "lidar",
        CYLINDER,
        [0.045, 0.025, 0],
        rgba=DARK_RGBA,
        material="rubber",
        pos=[g.base_half[0] - 0.07, 0, top + 0.025],
    )


def _add_head(torso: mujoco.MjsBody) -> None:
    g = GEOMETRY
    neck = torso.add_body(name="neck", pos=[-0.03, 0, g.head_z], gravcomp=1.0)
    neck.add_joint(
        name=HEAD_JOINTS[0],
        type=HINGE,
        axis=[0, 0, 1],
        range=[-1.6, 1.6],
        limited=mujoco.mjtLimited.mjLIMITED_TRUE,
        armature=0.01,
        damping=0.5,
    )
    stem = neck.add_geom(
        type=CYLINDER,
        size=[0.03, 0.05, 0],
        pos=[0, 0, -0.05],
        rgba=list(DARK_RGBA),
        material="rubber",
        mass=0.3,
    )
    set_visual_only(stem)
    head = neck.add_body(name="head", pos=[0, 0, 0.04], gravcomp=1.0)
    head.add_joint(
        name=HEAD_JOINTS[1],
        type=HINGE,
        axis=[0, 1, 0],
        range=[-0.8, 1.2],
        limited=mujoco.mjtLimited.mjLIMITED_TRUE,
        armature=0.01,
        damping=0.5,
    )
    skull = head.add_geom(
        name="head_shell",
        type=BOX,
        size=[0.07, 0.11, 0.06],
        rgba=list(BODY_RGBA),
        material="robot_shell",
        mass=1.0,
    )
    set_visual_only(skull)
    visor = head.add_geom(
        type=BOX,
        size=[0.01, 0.09, 0.025],
        pos=[0.07, 0, 0.005],
        rgba=list(DARK_RGBA),
        material="rubber",
        mass=0.05,
    )
    set_visual_only(visor)
    # Camera looks along the head's +x with +z up (MuJoCo cameras look down their -z).
    head.add_camera(name="head_cam", pos=[0.08, 0, 0.0], xyaxes=[0, -1, 0, 0, 0, 1], fovy=70)


def _add_arm(torso: mujoco.MjsBody, side: str, mount: Vec3) -> None:
    names = arm_joint_names(side)
    parent = torso.add_body(name=f"arm_{side}_link0", pos=list(mount), gravcomp=1.0)
    plinth = parent.add_geom(
        type=CYLINDER,
        size=[0.06, 0.03, 0],
        pos=[0, 0, 0.03],
        rgba=list(DARK_RGBA),
        material="rubber",
        mass=1.0,
    )
    set_visual_only(plinth)
    for i, link in enumerate(panda.DH):
        quat: Quat = quat_axis_angle((1, 0, 0), link.alpha)
        offset = rotate(quat, (0.0, 0.0, link.d))
        pos = np.array([link.a, 0.0, 0.0]) + offset
        body = parent.add_body(
            name=f"arm_{side}_link{i + 1}", pos=pos.tolist(), quat=list(quat), gravcomp=1.0
        )
        low, high = panda.JOINT_LIMITS[i]
        body.add_joint(
            name=names[i],
            type=HINGE,
            axis=[0, 0, 1],
            range=[low, high],
            limited=mujoco.mjtLimited.mjLIMITED_TRUE,
            armature=0.1,
            damping=1.0,
        )
        _add_link_geom(parent, pos, side, i, mass=panda.LINK_MASSES[i])
        # A dark collar around each joint's axis, as on the real arm: the links read as
        # links, the joints as joints.
        add_decor(
            body,
            f"arm_{side}_collar{i + 1}",
            CYLINDER,
            [0.068 - 0.002 * i, 0.032, 0],
            rgba=DARK_RGBA,
            material="rubber",
        )
        parent = body
    _add_link_geom(parent, np.array([0.0, 0.0, panda.FLANGE_D]), side, 7, mass=0.2)
    _add_hand(parent, side)


def _add_link_geom(
    parent: mujoco.MjsBody, child_pos: np.ndarray, side: str, index: int, mass: float
) -> None:
    """A capsule from ``parent``'s origin to its child's origin, the arm's visible link."""
    # Radii shrink a little link by link so that neighbouring links' rounded ends do not
    # coincide (coincident surfaces flicker when rendered).
    radius = 0.062 - 0.002 * index
    length = float(np.linalg.norm(child_pos))
    rgba = ACCENT_RGBA if index in (1, 3, 5) else BODY_RGBA
    if length < 1e-6:
        geom = parent.add_geom(
            name=f"arm_{side}_geom{index}", type=SPHERE, size=[radius, 0, 0], mass=mass
        )
    else:
        geom = parent.add_geom(
            name=f"arm_{side}_geom{index}",
            type=CAPSULE,
            fromto=[0, 0, 0, *child_pos.tolist()],
            size=[radius, 0, 0],
            mass=mass,
        )
    geom.rgba = list(rgba)
    geom.material = "robot_shell"
    set_robot_collision(geom)


def _add_hand(link7: mujoco.MjsBody, side: str) -> None:
    g = GEOMETRY
    hand = link7.add_body(
        name=f"hand_{side}",
        pos=[0, 0, panda.FLANGE_D],
        quat=list(quat_axis_angle((0, 0, 1), -math.pi / 4)),
        gravcomp=1.0,
    )
    housing = hand.add_geom(
        name=f"hand_{side}_housing",
        type=BOX,
        size=[0.03, 0.07, 0.03],
        pos=[0, 0, 0.03],
        rgba=list(DARK_RGBA),
        material="rubber",
        mass=0.6,
    )
    set_robot_collision(housing)
    post = hand.add_geom(
        type=CYLINDER,
        size=[0.02, 0.03, 0],
        pos=[0, 0, 0.08],
        rgba=list(DARK_RGBA),
        material="rubber",
        mass=0.05,
    )
    set_visual_only(post)
    pad = hand.add_geom(
        name=f"pad_{side}",
        type=BOX,
        size=list(g.pad_half),
        pos=[0, 0, g.pad_center_z],
        rgba=list(PAD_RGBA),
        material="rubber",
        mass=0.1,
        friction=[1.0, 0.02, 0.002],
        condim=4,
        priority=1,
    )
    set_robot_collision(pad)
    hand.add_site(name=f"tcp_{side}", pos=[0, 0, TCP_OFFSET_Z], size=[0.01, 0, 0])
    hand.add_camera(
        name=f"wrist_{side}_cam",
        pos=[0.06, 0, 0.04],
        quat=list(quat_axis_angle((1, 0, 0), math.pi)),
        fovy=80,
    )
    for j, sign in enumerate((1.0, -1.0)):
        finger = hand.add_body(name=f"finger_{side}_{'ab'[j]}", pos=[0, 0, 0.06], gravcomp=1.0)
        finger.add_joint(
            name=FINGER_JOINTS[side][j],
            type=SLIDE,
            axis=[0, sign, 0],
            range=[0.0, g.finger_open],
            limited=mujoco.mjtLimited.mjLIMITED_TRUE,
            armature=0.01,
            damping=2.0,
        )
        jaw = finger.add_geom(
            type=BOX,
            size=[0.012, 0.008, 0.028],
            pos=[0, sign * 0.014, 0.03],
            rgba=list(DARK_RGBA),
            material="rubber",
            mass=0.02,
        )
        set_visual_only(jaw)


def _add_actuators(spec: mujoco.MjSpec) -> None:
    def position(
        joint: str, kp: float, kv: float, force: float | None = None, limited: bool = True
    ) -> None:
        act = spec.add_actuator(name=joint, target=joint)
        act.trntype = mujoco.mjtTrn.mjTRN_JOINT
        act.set_to_position(kp=kp, kv=kv)
        if limited:
            act.inheritrange = 1.0
        if force is not None:
            act.forcelimited = mujoco.mjtLimited.mjLIMITED_TRUE
            act.forcerange = [-force, force]

    position(BASE_JOINTS[0], kp=3.0e4, kv=4.0e3, limited=False)
    position(BASE_JOINTS[1], kp=3.0e4, kv=4.0e3, limited=False)
    position(BASE_JOINTS[2], kp=6.0e3, kv=8.0e2, limited=False)
    position(SPINE_JOINT, kp=2.0e4, kv=2.0e3)
    for joint in HEAD_JOINTS:
        position(joint, kp=20.0, kv=2.0)
    for side in SIDES:
        for i, joint in enumerate(arm_joint_names(side)):
            position(joint, kp=panda.POSITION_GAINS[i], kv=panda.DAMPING_GAINS[i])
        for joint in FINGER_JOINTS[side]:
            position(joint, kp=300.0, kv=10.0, force=40.0)

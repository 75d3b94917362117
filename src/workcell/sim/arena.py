"""The factory workcell around the robot: floor, conveyor, delivery table, boxes, context.

Built with MjSpec from a :class:`WorldConfig`. Boxes are free bodies kept in a parked pool
(no gravity, no contacts) until the feeder releases them onto the belt start.
"""

from __future__ import annotations

from collections.abc import Sequence

import mujoco

from workcell.sim.config import WorldConfig, longest_box
from workcell.sim.looks import add_decor, add_looks
from workcell.sim.spec_utils import set_env_collision, set_visual_only

BOX = mujoco.mjtGeom.mjGEOM_BOX
PLANE = mujoco.mjtGeom.mjGEOM_PLANE
CYLINDER = mujoco.mjtGeom.mjGEOM_CYLINDER

BELT_THICKNESS = 0.04
STOP_THICKNESS = 0.04
PARK_Z = -1.0
"""Parked boxes float out of sight under the floor."""

FRAME_RGBA = (0.35, 0.37, 0.4, 1.0)
BELT_RGBA = (0.12, 0.12, 0.13, 1.0)
SAFETY_RGBA = (0.95, 0.75, 0.1, 1.0)
TABLE_RGBA = (0.45, 0.5, 0.55, 1.0)
ZONE_RGBA = (0.2, 0.75, 0.35, 1.0)
WALL_RGBA = (0.82, 0.83, 0.8, 1.0)


def box_name(i: int) -> str:
    return f"box_{i}"


def weld_name(i: int) -> str:
    return f"grasp_weld_{i}"


def parked_position(i: int) -> tuple[float, float, float]:
    return (-2.5 + 0.8 * i, -2.0, PARK_Z)


def pickup_plate_length(config: WorldConfig) -> float:
    """Length of the still plate between the belt's end and the end stop."""
    return longest_box(config) + 0.03


def pickup_range_x(config: WorldConfig) -> tuple[float, float]:
    """Where along x a box's centre comes to rest on the pickup plate: fully off the belt,
    short of the end stop."""
    c, half = config.conveyor, config.box.size[0] / 2
    return c.end_x - pickup_plate_length(config) + half, c.end_x - half


def build_arena(spec: mujoco.MjSpec, config: WorldConfig) -> None:
    """Add everything except the robot to ``spec``."""
    _add_visual_assets(spec)
    floor = spec.worldbody.add_geom(
        name="floor", type=PLANE, size=[8, 8, 0.1], material="floor_mat"
    )
    set_env_collision(floor)
    _add_conveyor(spec, config)
    _add_target(spec, config)
    _add_context(spec)
    _add_floor_markings(spec, config)
    _add_boxes(spec, config)


def _add_visual_assets(spec: mujoco.MjSpec) -> None:
    spec.add_texture(
        name="floor_tex",
        type=mujoco.mjtTexture.mjTEXTURE_2D,
        builtin=mujoco.mjtBuiltin.mjBUILTIN_CHECKER,
        rgb1=[0.45, 0.46, 0.47],
        rgb2=[0.41, 0.42, 0.44],
        # Joints between 2 m concrete slabs.
        mark=mujoco.mjtMark.mjMARK_EDGE,
        markrgb=[0.3, 0.31, 0.32],
        width=256,
        height=256,
    )
    mat = spec.add_material(
        name="floor_mat", texrepeat=[8, 8], reflectance=0.0, specular=0.15, shininess=0.2
    )
    mat.textures[mujoco.mjtTextureRole.mjTEXROLE_RGB] = "floor_tex"
    add_looks(spec, "painted_steel", "floor_paint", "rubber", "cardboard", "plaster")
    spec.visual.headlight.ambient = [0.35, 0.35, 0.35]
    spec.visual.headlight.diffuse = [0.5, 0.5, 0.5]
    spec.add_texture(
        name="sky",
        type=mujoco.mjtTexture.mjTEXTURE_SKYBOX,
        builtin=mujoco.mjtBuiltin.mjBUILTIN_GRADIENT,
        rgb1=[0.75, 0.8, 0.85],
        rgb2=[0.35, 0.38, 0.42],
        width=256,
        height=256,
    )
    sun = spec.worldbody.add_light(name="sun", pos=[0, 0, 6], dir=[0.2, 0.3, -1], diffuse=[0.6] * 3)
    sun.type = mujoco.mjtLightType.mjLIGHT_DIRECTIONAL
    spec.worldbody.add_light(name="lamp_feed", pos=[-2, 0, 4], dir=[0, 0, -1], diffuse=[0.3] * 3)
    spec.worldbody.add_light(name="lamp_target", pos=[2, 2, 4], dir=[0, 0, -1], diffuse=[0.3] * 3)


def _add_conveyor(spec: mujoco.MjSpec, config: WorldConfig) -> None:
    c = config.conveyor
    mid_x = (c.start_x + c.end_x) / 2
    conveyor = spec.worldbody.add_body(name="conveyor", pos=[mid_x, c.center_y, 0])
    plate = pickup_plate_length(config)
    belt_length = c.length - plate
    belt = conveyor.add_geom(
        name="belt",
        type=BOX,
        size=[belt_length / 2, c.width / 2, BELT_THICKNESS / 2],
        pos=[-plate / 2, 0, c.height - BELT_THICKNESS / 2],
        rgba=list(BELT_RGBA),
        material="rubber",
        friction=[1.0, 0.005, 0.0001],
    )
    belt.surfacevel = [c.speed, 0, 0, 0, 0, 0]
    set_env_collision(belt)
    # A still plate at the belt's end: a box slides onto it and stops at rest (pressed
    # against a stop by a running belt, it would shake forever).
    pickup = conveyor.add_geom(
        name="pickup_plate",
        type=BOX,
        size=[plate / 2, c.width / 2, BELT_THICKNESS / 2],
        pos=[c.length / 2 - plate / 2, 0, c.height - BELT_THICKNESS / 2],
        rgba=[0.3, 0.3, 0.32, 1],
        material="painted_steel",
        friction=[1.0, 0.005, 0.0001],
    )
    set_env_collision(pickup)
    frame_h = c.height - BELT_THICKNESS
    frame = conveyor.add_geom(
        name="conveyor_frame",
        type=BOX,
        size=[c.length / 2, c.width / 2 + 0.03, frame_h / 2 - 0.15],
        pos=[0, 0, frame_h / 2 + 0.15],
        rgba=list(FRAME_RGBA),
        material="painted_steel",
    )
    set_env_collision(frame)
    for sign in (1.0, -1.0):
        rail = conveyor.add_geom(
            name=f"rail_{'l' if sign > 0 else 'r'}",
            type=BOX,
            size=[c.length / 2, 0.015, 0.02],
            pos=[0, sign * (c.width / 2 + 0.015), c.height + 0.01],
            rgba=list(SAFETY_RGBA),
            material="painted_steel",
        )
        set_env_collision(rail)
        for x in (-c.length / 2 + 0.1, 0.0, c.length / 2 - 0.1):
            leg = conveyor.add_geom(
                type=BOX,
                size=[0.03, 0.03, 0.075],
                pos=[x, sign * (c.width / 2 - 0.01), 0.075],
                rgba=list(FRAME_RGBA),
                material="painted_steel",
            )
            set_visual_only(leg)
    stop = conveyor.add_geom(
        name="end_stop",
        type=BOX,
        size=[STOP_THICKNESS / 2, c.width / 2 + 0.03, 0.05],
        pos=[c.length / 2 + STOP_THICKNESS / 2, 0, c.height + 0.01],
        rgba=list(SAFETY_RGBA),
        material="painted_steel",
    )
    set_env_collision(stop)
    # The feeding zone: a gantry over the belt start where boxes appear.
    for sign in (1.0, -1.0):
        post = conveyor.add_geom(
            type=BOX,
            size=[0.03, 0.03, (c.height + 0.55) / 2],
            pos=[-c.length / 2 + 0.25, sign * (c.width / 2 + 0.08), (c.height + 0.55) / 2],
            rgba=list(SAFETY_RGBA),
            material="painted_steel",
        )
        set_visual_only(post)
    beam = conveyor.add_geom(
        name="feeder_beam",
        type=BOX,
        size=[0.05, c.width / 2 + 0.11, 0.04],
        pos=[-c.length / 2 + 0.25, 0, c.height + 0.55],
        rgba=list(SAFETY_RGBA),
        material="painted_steel",
    )
    set_visual_only(beam)


def _add_target(spec: mujoco.MjSpec, config: WorldConfig) -> None:
    t = config.target
    add_zone_table(
        spec,
        config,
        center=t.center,
        body="target",
        top="target_top",
        zone="target_zone",
        zone_rgba=(*ZONE_RGBA[:3], 0.6),
    )


def add_zone_table(
    spec: mujoco.MjSpec,
    config: WorldConfig,
    *,
    center: Sequence[float],
    body: str,
    top: str,
    zone: str,
    zone_rgba: Sequence[float],
) -> mujoco.MjsBody:
    """A table the size of the delivery table (``world.target``) at ``center`` (x, y), its
    zone marked on its top: the delivery table, and sort's sorting table. ``body``, ``top``
    and ``zone`` name the table's body and its two named geoms."""
    t = config.target
    table = spec.worldbody.add_body(name=body, pos=[center[0], center[1], 0])
    top_geom = table.add_geom(
        name=top,
        type=BOX,
        size=[t.zone[0] / 2 + 0.05, t.zone[1] / 2 + 0.05, 0.02],
        pos=[0, 0, t.table_height - 0.02],
        rgba=list(TABLE_RGBA),
        material="painted_steel",
        friction=[1.0, 0.005, 0.0001],
    )
    set_env_collision(top_geom)
    zone_geom = table.add_geom(
        name=zone,
        type=BOX,
        size=[t.zone[0] / 2, t.zone[1] / 2, 0.001],
        pos=[0, 0, t.table_height + 0.001],
        rgba=list(zone_rgba),
    )
    set_visual_only(zone_geom)
    for sx in (1.0, -1.0):
        for sy in (1.0, -1.0):
            leg = table.add_geom(
                type=BOX,
                size=[0.03, 0.03, (t.table_height - 0.04) / 2],
                pos=[sx * t.zone[0] / 2, sy * t.zone[1] / 2, (t.table_height - 0.04) / 2],
                rgba=list(FRAME_RGBA),
                material="painted_steel",
            )
            set_env_collision(leg)
    return table


def _add_context(spec: mujoco.MjSpec) -> None:
    """Walls and storage racks: scenery only, nothing collides with them."""
    for name, pos, size in (
        ("wall_back", (-5.0, 0.0, 1.5), (0.05, 5.0, 1.5)),
        ("wall_left", (0.0, 5.0, 1.5), (5.0, 0.05, 1.5)),
        ("wall_right", (0.0, -5.0, 1.5), (5.0, 0.05, 1.5)),
        ("wall_front", (5.0, 0.0, 1.5), (0.05, 5.0, 1.5)),
    ):
        wall = spec.worldbody.add_geom(
            name=name,
            type=BOX,
            pos=list(pos),
            size=list(size),
            rgba=list(WALL_RGBA),
            material="plaster",
        )
        set_visual_only(wall)
    for k, (x, y) in enumerate(((-2.5, 4.3), (-0.5, 4.3), (-2.5, -4.3), (3.5, -4.3))):
        rack = spec.worldbody.add_body(name=f"rack_{k}", pos=[x, y, 0])
        for sx in (1.0, -1.0):
            for sy in (1.0, -1.0):
                upright = rack.add_geom(
                    type=BOX,
                    size=[0.03, 0.03, 1.1],
                    pos=[sx * 0.8, sy * 0.3, 1.1],
                    rgba=[0.2, 0.35, 0.7, 1],
                    material="painted_steel",
                )
                set_visual_only(upright)
        for level in (0.4, 1.1, 1.8):
            shelf = rack.add_geom(
                type=BOX,
                size=[0.82, 0.32, 0.015],
                pos=[0, 0, level],
                rgba=[0.8, 0.45, 0.1, 1],
                material="painted_steel",
            )
            set_visual_only(shelf)
            for j in (-0.45, 0.1, 0.5):
                crate = rack.add_geom(
                    type=BOX,
                    size=[0.15, 0.15, 0.12],
                    pos=[j, 0, level + 0.135],
                    rgba=[0.7, 0.55, 0.35, 1],
                    material="cardboard",
                )
                set_visual_only(crate)
    pole = spec.worldbody.add_geom(
        type=CYLINDER,
        size=[0.12, 1.5, 0],
        pos=[3.2, 3.2, 1.5],
        rgba=list(SAFETY_RGBA),
        material="painted_steel",
    )
    set_visual_only(pole)
    stripe = spec.worldbody.add_geom(
        type=BOX,
        size=[2.5, 0.04, 0.001],
        pos=[1.5, -1.0, 0.001],
        rgba=list(SAFETY_RGBA),
        material="floor_paint",
    )
    set_visual_only(stripe)


def _add_floor_markings(spec: mujoco.MjSpec, config: WorldConfig) -> None:
    """Safety-yellow lines on the floor: a keep-clear frame around the conveyor, one around
    the delivery table, and hatching under the feeder where boxes arrive."""
    c, t = config.conveyor, config.target
    line = 0.04

    def frame(name: str, x0: float, x1: float, y0: float, y1: float) -> None:
        for i, (cx, cy, hx, hy) in enumerate(
            (
                ((x0 + x1) / 2, y0, (x1 - x0) / 2 + line, line / 2),
                ((x0 + x1) / 2, y1, (x1 - x0) / 2 + line, line / 2),
                (x0, (y0 + y1) / 2, line / 2, (y1 - y0) / 2),
                (x1, (y0 + y1) / 2, line / 2, (y1 - y0) / 2),
            )
        ):
            add_decor(
                spec.worldbody,
                f"{name}_line_{i}",
                BOX,
                [hx, hy, 0.001],
                rgba=SAFETY_RGBA,
                material="floor_paint",
                pos=[cx, cy, 0.002],
            )

    margin = 0.25
    half_w = c.width / 2 + 0.11 + margin
    frame(
        "conveyor", c.start_x - margin, c.end_x + margin, c.center_y - half_w, c.center_y + half_w
    )
    hx, hy = t.zone[0] / 2 + 0.05 + margin, t.zone[1] / 2 + 0.05 + margin
    frame("table", t.center[0] - hx, t.center[0] + hx, t.center[1] - hy, t.center[1] + hy)
    # Hatching: diagonal bars beside the feeder gantry, on the side the robot never needs.
    diagonal = [0.9238795, 0.0, 0.0, 0.3826834]  # 45 degrees about z
    for k in range(4):
        add_decor(
            spec.worldbody,
            f"feeder_hatch_{k}",
            BOX,
            [0.2, 0.03, 0.001],
            rgba=SAFETY_RGBA,
            material="floor_paint",
            pos=[c.start_x + 0.05 + 0.22 * k, c.center_y - half_w + 0.22, 0.002],
            quat=diagonal,
        )


def _add_boxes(spec: mujoco.MjSpec, config: WorldConfig) -> None:
    b = config.box
    half = [s / 2 for s in b.size]
    for i in range(config.feeder.pool_size):
        body = spec.worldbody.add_body(name=box_name(i), pos=list(parked_position(i)), gravcomp=1.0)
        body.add_freejoint(name=f"{box_name(i)}_joint")
        geom = body.add_geom(
            name=f"{box_name(i)}_geom",
            type=BOX,
            size=half,
            mass=b.mass,
            rgba=list(b.rgba),
            material="cardboard",
            friction=[0.9, 0.02, 0.002],
            condim=4,
        )
        geom.contype, geom.conaffinity = 0, 0
        tape = body.add_geom(
            type=BOX,
            size=[half[0] + 0.001, 0.03, 0.002],
            pos=[0, 0, half[2]],
            rgba=[0.85, 0.75, 0.55, 1],
            material="plaster",
            mass=0.001,
        )
        set_visual_only(tape)
        weld = spec.add_equality(
            name=weld_name(i),
            type=mujoco.mjtEq.mjEQ_WELD,
            objtype=mujoco.mjtObj.mjOBJ_BODY,
            name1="hand_l",
            name2=box_name(i),
            active=False,
        )
        weld.solref = [0.01, 1.0]

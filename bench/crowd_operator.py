"""An emulated remote operator with the expert's behaviour, for ``bench/crowd.py``.

It sees only what a browser sees over the socket (the scene's bodies, each State's poses,
arm targets and following flags, the HUD, task events) and decides phase by phase what the
scripted expert does: wait for a box at the end of the belt, drive up to it, take both
grips, turn the palms inward, reach around the box, squeeze, close both grippers, lift,
carry it to the table, set it down, let go, back off. Its decisions become the Input
messages an emulated headset sends: thumbsticks for the base, controller poses moved so
the arm targets (the clutch follows a held controller's displacement) go where the hands
should, grips and triggers. It is the Python twin of the browser tests' scripted operator
(``web/tests/e2e/operator.ts``), so a session driven by it does the work a person's does
(driving, grasp contacts, a carried box) and can succeed.
"""

from __future__ import annotations

import math
import re
import time
from dataclasses import dataclass, field
from typing import Any

from workcell.protocol import messages as m

Vec3 = tuple[float, float, float]
Base = tuple[float, float, float]
"""A base pose in the world: x, y, yaw."""
Pose = tuple[float, float, float, float, float, float, float]

BOX_HALF = 0.15  # half the default box width across the belt (the grasp axis)
BELT_TOP = 0.75
PICK_DISTANCE = 0.6
PREGRASP_GAP = 0.07
SQUEEZE_GAP = -0.006
LIFT: Vec3 = (-0.05, 0.0, 0.12)
TABLE_TOP = 0.6
PLACE_DISTANCE = 0.8
ARM_REACH = 0.65
DEAD_ZONE = 0.15
SETTLE_AFTER_S = 10.0  # on the last leg to the table this long (sim time)...
SETTLED_TOLERANCE = 0.06  # ...close enough is this close (m)
TOLERANCE = 0.015
TCP_OFFSET = 0.1375  # the TCP sits this far along the hand's z axis
REST = {"l": (-0.2, 1.0, -0.3), "r": (0.2, 1.0, -0.3)}
"""Where the controllers rest (WebXR local-floor: x right, y up, -z forward)."""
S = math.sqrt(0.5)
PALM_IN: dict[str, tuple[float, float, float, float]] = {
    "l": (S, 0.0, 0.0, S),
    "r": (S, 0.0, 0.0, -S),
}
NEUTRAL = (1.0, 0.0, 0.0, 0.0)
HEADSET: Pose = (0.0, 1.6, 0.0, math.cos(-0.2), math.sin(-0.2), 0.0, 0.0)
BOX_NAME = re.compile(r"^box_\d+$")


def wrap(angle: float) -> float:
    return math.atan2(math.sin(angle), math.cos(angle))


def yaw_of(pose: Pose) -> float:
    w, x, y, z = pose[3:]
    return math.atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))


def to_base(base: Base, p: Vec3) -> Vec3:
    bx, by, yaw = base
    dx, dy = p[0] - bx, p[1] - by
    c, s = math.cos(yaw), math.sin(yaw)
    return (c * dx + s * dy, -s * dx + c * dy, p[2])


def add(a: Vec3, b: Vec3) -> Vec3:
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


def sub(a: Vec3, b: Vec3) -> Vec3:
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def norm(a: Vec3) -> float:
    return math.hypot(*a)


def tcp_of(pose: Pose) -> Vec3:
    x, y, z, w, qx, qy, qz = pose
    return (
        x + TCP_OFFSET * 2 * (qx * qz + w * qy),
        y + TCP_OFFSET * 2 * (qy * qz - w * qx),
        z + TCP_OFFSET * (1 - 2 * (qx * qx + qy * qy)),
    )


@dataclass(frozen=True)
class Observation:
    """What the operator sees in one look."""

    t: float
    running: bool
    base: Base
    boxes: dict[str, Pose]
    tcp: tuple[Vec3, Vec3]
    targets: tuple[Vec3, Vec3]
    following: tuple[bool, bool]
    holding: bool
    zone: tuple[float, float]


class View:
    """What the socket has shown so far: the scene's bodies, the newest State and whether
    the hands hold a box (from the task events)."""

    def __init__(self) -> None:
        self.names: list[str] = []
        """Dynamic bodies in State pose order."""
        self.fixed: dict[str, Pose] = {}
        self.state: dict[str, Any] | None = None
        self.holding = False
        self.trials_started = 0

    def take(self, message: dict[str, Any]) -> None:
        kind = message["type"]
        if kind == "scene":
            bodies = sorted(message["bodies"], key=lambda b: b["index"])
            self.names = [b["name"] for b in bodies if b["dynamic"]]
            self.fixed = {b["name"]: tuple(b["pose"]) for b in bodies if not b["dynamic"]}
        elif kind == "state":
            self.state = message
        elif kind == "event":
            if message["kind"] == "grasp_changed":
                self.holding = bool(message["engaged"])
            elif message["kind"] in ("trial_started", "countdown_started"):
                self.holding = False
                self.trials_started += message["kind"] == "trial_started"

    def observe(self) -> Observation | None:
        state = self.state
        if state is None or not self.names:
            return None
        bodies: dict[str, Pose] = dict(self.fixed)
        bodies.update(zip(self.names, (tuple(p) for p in state["poses"]), strict=False))
        base_pose = bodies["base"]
        targets = state["tcp_targets"]
        zone = bodies.get("target")
        hud = state.get("hud") or {}
        return Observation(
            t=float(state["t_sim"]),
            running=hud.get("phase") == "running",
            base=(base_pose[0], base_pose[1], yaw_of(base_pose)),
            boxes={name: pose for name, pose in bodies.items() if BOX_NAME.match(name)},
            tcp=(tcp_of(bodies["hand_l"]), tcp_of(bodies["hand_r"])),
            targets=(tuple(targets[0][:3]), tuple(targets[1][:3])),
            following=(bool(state["following"][0]), bool(state["following"][1])),
            holding=self.holding,
            zone=(zone[0], zone[1]) if zone is not None else (1.6, 1.9),
        )


@dataclass
class Drive:
    forward: float = 0.0
    left: float = 0.0
    turn: float = 0.0


@dataclass
class ExpertLikeOperator:
    """The expert's phases, decided from observations (see the module's docstring)."""

    lead: float = 0.0
    """Drive on where the base will be after this long (the loop's latency), s."""
    phase: str = "wait"
    phase_start: float | None = None
    box: str | None = None
    route: list[Base] = field(default_factory=list)
    targets: tuple[Vec3, Vec3] | None = None
    grip: bool = False
    trigger: bool = False
    palms_in: bool = False
    drive: Drive = field(default_factory=Drive)
    velocity: Vec3 = (0.0, 0.0, 0.0)
    last: tuple[float, Base] | None = None
    candidate: tuple[str, Vec3] | None = None
    lifted: float | None = None
    lowering: float | None = None
    leg_start: float | None = None
    phases: list[tuple[float, str]] = field(default_factory=list)

    def enter(self, phase: str, t: float) -> None:
        self.phase, self.phase_start = phase, t
        self.phases.append((round(t, 2), phase))

    def drive_to(self, obs: Observation, goal: Base, tolerance: float, vmax: float = 0.5) -> bool:
        """Sticks that move the base toward ``goal``; whether it is there."""
        vx, vy, wz = self.velocity
        lead = self.lead
        ahead = (obs.base[0] + vx * lead, obs.base[1] + vy * lead, obs.base[2] + wz * lead)
        ex, ey, _ = to_base(ahead, (goal[0], goal[1], 0.0))
        dist = math.hypot(ex, ey)
        eyaw = wrap(goal[2] - ahead[2])
        yaw_tolerance = 0.03 * max(1.0, tolerance / 0.015)
        here = to_base(obs.base, (goal[0], goal[1], 0.0))
        arrived = (
            math.hypot(here[0], here[1]) < tolerance
            and abs(wrap(goal[2] - obs.base[2])) < yaw_tolerance
        )
        gain = min(1.0, 0.3 / max(lead, 0.3))
        v = 0.0 if dist < tolerance * 0.5 else min(vmax, 1.2 * gain * dist)
        magnitude = DEAD_ZONE + (1 - DEAD_ZONE) * min(1.0, v / 0.8) if v > 0 else 0.0
        w = max(-1.0, min(1.0, 2 * gain * eyaw))
        turn = (
            0.0
            if abs(eyaw) < 0.01
            else -(DEAD_ZONE + (1 - DEAD_ZONE) * min(1.0, abs(w) / 1.2)) * math.copysign(1, w)
        )
        self.drive = Drive(
            forward=ex / dist * magnitude if v > 0 else 0.0,
            left=ey / dist * magnitude if v > 0 else 0.0,
            turn=turn,
        )
        return arrived

    def standing_still(self) -> bool:
        return (
            math.hypot(self.velocity[0], self.velocity[1]) < 0.03 and abs(self.velocity[2]) < 0.05
        )

    def palms(self, obs: Observation, gap: float, lift: float = 0.0) -> tuple[Vec3, Vec3]:
        assert self.box is not None
        c = to_base(obs.base, obs.boxes[self.box][:3])
        z = c[2] + lift
        return (c[0], c[1] + BOX_HALF + gap, z), (c[0], c[1] - BOX_HALF - gap, z)

    def hands_at(self, obs: Observation, tolerance: float) -> bool:
        if self.targets is None:
            return False
        return all(
            norm(sub(to_base(obs.base, tcp), target)) < tolerance
            for tcp, target in zip(obs.tcp, self.targets, strict=True)
        )

    def _track(self, obs: Observation) -> None:
        if self.last is not None and obs.t > self.last[0]:
            dt = obs.t - self.last[0]
            then = self.last[1]
            now = (
                (obs.base[0] - then[0]) / dt,
                (obs.base[1] - then[1]) / dt,
                wrap(obs.base[2] - then[2]) / dt,
            )
            k = min(1.0, dt / 0.15)  # low-pass over ~0.15 s
            self.velocity = (
                self.velocity[0] + k * (now[0] - self.velocity[0]),
                self.velocity[1] + k * (now[1] - self.velocity[1]),
                self.velocity[2] + k * (now[2] - self.velocity[2]),
            )
        self.last = (obs.t, obs.base)

    def step(self, obs: Observation) -> None:
        self._track(obs)
        if self.phase_start is None:
            self.phase_start = obs.t
        t = obs.t
        elapsed = t - self.phase_start
        if self.phase == "wait":
            self.grip = self.trigger = False
            self.drive_to(obs, (1.0, 0.0, math.pi), TOLERANCE)
            resting = [
                (pose[0], name)
                for name, pose in obs.boxes.items()
                if abs(pose[2] - (BELT_TOP + BOX_HALF)) < 0.03 and -0.5 < pose[0] < 0.2
            ]
            if resting and obs.running:
                _, name = max(resting)
                position = obs.boxes[name][:3]
                candidate = self.candidate
                if candidate and candidate[0] == name and norm(sub(position, candidate[1])) < 0.003:
                    self.box = name
                    self.enter("approach", t)
                self.candidate = (name, position)
        elif self.phase == "approach":
            assert self.box is not None
            pose = obs.boxes[self.box]
            heading = math.pi + wrap(yaw_of(pose))
            goal = (
                pose[0] - PICK_DISTANCE * math.cos(heading),
                pose[1] - PICK_DISTANCE * math.sin(heading),
                heading,
            )
            if self.drive_to(obs, goal, TOLERANCE, 0.6) and self.standing_still():
                self.drive = Drive()
                self.enter("engage", t)
        elif self.phase == "engage":
            self.drive = Drive()
            self.grip, self.palms_in = True, False
            if obs.following[0] and obs.following[1]:
                self.targets = self.palms(obs, PREGRASP_GAP)
                self.palms_in = True
                self.enter("pregrasp", t)
        elif self.phase == "pregrasp":
            self.targets = self.palms(obs, PREGRASP_GAP)
            if (self.hands_at(obs, 0.02) and elapsed > 0.5) or elapsed > 8:
                self.enter("squeeze", t)
        elif self.phase == "squeeze":
            self.targets = self.palms(obs, SQUEEZE_GAP)
            if self.hands_at(obs, 0.03) or elapsed > 3:
                self.trigger = True
            if obs.holding:
                self.enter("lift", t)
            elif elapsed > 8:
                self.trigger = False
                self.enter("pregrasp", t)
        elif self.phase == "lift":
            if self.lifted != self.phase_start and self.targets is not None:
                self.lifted = self.phase_start
                self.targets = (add(self.targets[0], LIFT), add(self.targets[1], LIFT))
            if (self.hands_at(obs, 0.03) and elapsed > 0.5) or elapsed > 3:
                bx, by, yaw = obs.base
                retreat = (bx - 0.5 * math.cos(yaw), by - 0.5 * math.sin(yaw), yaw)
                zx, zy = obs.zone
                dx, dy = zx - retreat[0], zy - retreat[1]
                if abs(dx) > abs(dy):
                    h = 0.0 if dx > 0 else math.pi
                else:
                    h = math.pi / 2 if dy > 0 else -math.pi / 2
                h = yaw + wrap(h - yaw)
                table = (zx - PLACE_DISTANCE * math.cos(h), zy - PLACE_DISTANCE * math.sin(h), h)
                self.route = [retreat, table]
                self.enter("carry", t)
        elif self.phase == "carry":
            if self.route:
                goal, last = self.route[0], len(self.route) == 1
                if self.leg_start is None:
                    self.leg_start = t
                settle = SETTLED_TOLERANCE if t - self.leg_start > SETTLE_AFTER_S else 0.0
                tolerance = max(0.02, TOLERANCE, settle) if last else 0.1
                arrived = self.drive_to(obs, goal, tolerance, 0.6)
                if arrived and (not last or self.standing_still()):
                    self.leg_start = None
                    self.route.pop(0)
                    if not self.route:
                        self.drive = Drive()
                        self.enter("place", t)
        elif self.phase == "place":
            # Hold the box where the hands have it and move the hands so that the box goes
            # first above its spot on the table, then down onto it.
            assert self.box is not None
            self.drive = Drive()
            goal = to_base(obs.base, (obs.zone[0], obs.zone[1], TABLE_TOP + BOX_HALF + 0.012))
            goal = (min(goal[0], ARM_REACH), goal[1], goal[2])
            held = to_base(obs.base, obs.boxes[self.box][:3])
            lowering = self.lowering == self.phase_start
            aim = goal if lowering else add(goal, (0.0, 0.0, 0.06))
            self.targets = (
                add(aim, sub(to_base(obs.base, obs.tcp[0]), held)),
                add(aim, sub(to_base(obs.base, obs.tcp[1]), held)),
            )
            off = norm(sub(aim, held))
            if not lowering and off < 0.03:
                self.lowering = self.phase_start
            if (lowering and off < 0.02) or elapsed > 8:
                self.enter("release", t)
        elif self.phase == "release":
            self.trigger = False
            if elapsed > 0.4:
                self.targets = self.palms(obs, 0.08, 0.02)
            if elapsed > 1.5:
                self.grip, self.targets = False, None
                bx, by, yaw = obs.base
                self.route = [(bx - 0.4 * math.cos(yaw), by - 0.4 * math.sin(yaw), yaw)]
                self.enter("backoff", t)
        elif self.phase == "backoff":
            if self.route and self.drive_to(obs, self.route[0], 0.05):
                self.route = []
            if not self.route:
                self.drive = Drive()


class ExpertLikeHeadset:
    """Turns the operator's decisions into the Input messages an emulated headset sends:
    each look, a held controller moves by a step that brings its arm's target (as the last
    State showed it) toward where the operator wants the hand."""

    def __init__(self) -> None:
        self.view = View()
        self.operator = ExpertLikeOperator()
        self.controllers: dict[str, Vec3] = dict(REST)
        self._trial = 0
        self._seq = 0
        self._corrected_with = 0
        """The input behind the last correction: the next waits for a State showing it."""

    def input(self, seq: int, lead_s: float) -> m.Input:
        if self.view.trials_started != self._trial:  # a new trial: start afresh
            self._trial = self.view.trials_started
            self.operator = ExpertLikeOperator()
            self.controllers = dict(REST)
        self._seq = seq
        operator = self.operator
        operator.lead = lead_s
        obs = self.view.observe()
        if obs is not None:
            operator.step(obs)
            self._follow(obs)
        if not operator.grip:
            self.controllers = dict(REST)
        grip = 1.0 if operator.grip else 0.0
        trigger = 1.0 if operator.trigger else 0.0
        drive = operator.drive

        def hand(side: str, stick: tuple[float, float]) -> m.ControllerState:
            quat = PALM_IN[side] if operator.palms_in else NEUTRAL
            return m.ControllerState((*self.controllers[side], *quat), grip, trigger, stick, 0)

        return m.Input(
            seq=seq,
            t_client=time.time(),
            source="xr",
            headset=HEADSET,
            left=hand("l", (-drive.left, drive.forward)),
            right=hand("r", (drive.turn, 0.0)),
        )

    def _follow(self, obs: Observation, gain: float = 0.7, max_step: float = 0.03) -> None:
        """Move each following hand's controller so its arm target nears the wanted one
        (base frame x forward, y left, z up is local-floor -z, -x, y)."""
        targets = self.operator.targets
        state = self.view.state
        if targets is None or state is None or state["input_seq"] < self._corrected_with:
            return  # the last correction has not shown yet: correcting again would overshoot
        self._corrected_with = self._seq
        for i, side in enumerate(("l", "r")):
            if not obs.following[i]:
                continue
            error = sub(targets[i], to_base(obs.base, obs.targets[i]))
            x, y, z = (max(-max_step, min(max_step, v * gain)) for v in error)
            self.controllers[side] = add(self.controllers[side], (-y, z, -x))

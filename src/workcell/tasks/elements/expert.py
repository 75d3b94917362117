"""The scripted expert: wait, approach, grasp with both arms, carry, place, release, back off.

It reads the world's state (box and robot poses) and emits nothing but :class:`Command`
values, exactly as a human operator's input would arrive, so its trials are recorded and
audited like anyone's.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from workcell.control.command import ArmCommand, BaseTwist, Command
from workcell.expert.grasp_geometry import PalmTargets, palm_targets
from workcell.expert.hands import measured_palms
from workcell.expert.phase import ExpertPhase
from workcell.expert.skill import ExpertConfig, SkillProfile
from workcell.sim.boxes import BoxSlot, BoxState
from workcell.sim.world import World
from workcell.tasks.elements.base_drive import ARRIVED_M, arrived_at, twist_toward, wrap_angle

REST_SPEED = 0.06
HAND_TOLERANCE_M = 0.02
PREGRASP_GAP = 0.07
RELEASE_GAP = 0.08
SQUEEZE = {"assisted": 0.006, "physical": 0.014}
STANDBY_DISTANCE = 1.0
RETREAT_DISTANCE = 0.5
PLACE_DISTANCE = 0.8
ARM_REACH = 0.6
LIFT = 0.1
PHASE_TIMEOUT_S = 12.0


@dataclass(frozen=True)
class Placement:
    """Where a carried box's centre goes: ``center`` (x, y in the world, m) and ``rest_z``,
    the height of its centre once it rests there."""

    center: NDArray[np.float64]
    rest_z: float


class ExpertOperator:
    """Delivers boxes one after another for as long as it is asked to act."""

    place_distance: float = PLACE_DISTANCE
    """How far (m) from where a box is set down the base stops to set it down."""

    def __init__(self, config: ExpertConfig | None = None, seed: int = 0) -> None:
        self.config = config or ExpertConfig()
        self.start_trial(seed)

    def start_trial(self, trial_seed: int) -> None:
        """Forget the last trial and draw this trial's behaviour from ``trial_seed``."""
        self._rng = np.random.default_rng(trial_seed)
        self.profile = SkillProfile.draw(self.config.skill, self._rng)
        self.phase = ExpertPhase.WAIT
        self.deliveries = 0
        self._box: BoxSlot | None = None
        self._phase_start = 0.0
        self._pause_until = 0.0
        self._palms: PalmTargets | None = None
        self._ready: PalmTargets | None = None
        self._noticed_at: float | None = None
        self._close = 0.0
        self._waypoints: list[NDArray[np.float64]] = []
        self._grasp_attempts = 0

    # --- the operator interface -------------------------------------------------------------

    def act(self, world: World) -> Command:
        """The command for the next control period."""
        t = world.time
        if t < self._pause_until:
            return self._command(world, BaseTwist())
        handler = {
            ExpertPhase.WAIT: self._wait,
            ExpertPhase.APPROACH: self._approach,
            ExpertPhase.PREGRASP: self._pregrasp,
            ExpertPhase.GRASP: self._grasp,
            ExpertPhase.LIFT: self._lift,
            ExpertPhase.RETREAT: self._retreat,
            ExpertPhase.CARRY: self._carry,
            ExpertPhase.PLACE: self._place,
            ExpertPhase.RELEASE: self._release,
            ExpertPhase.BACKOFF: self._backoff,
        }[self.phase]
        return self._command(world, handler(world))

    def resume(self, world: World, command: Command) -> None:
        """Go on from the world as someone else left it (a person who took over handed
        back): carry a box the hands hold to where it goes, else back off and wait for the
        next box. The palms start where the hands are, so the arms do not jump."""
        self._pause_until = 0.0
        self._noticed_at = None
        self._grasp_attempts = 0
        self._palms = measured_palms(world)
        self._box = world.grasp.holding
        self._close = 1.0 if self._box is not None else 0.0
        self._waypoints = [] if self._box is None else self._carry_route(world)
        self._enter(world, ExpertPhase.BACKOFF if self._box is None else ExpertPhase.CARRY)

    def placement(self, world: World, box: BoxSlot) -> Placement:
        """Where ``box`` is set down: the delivery zone's centre, at the height a box rests
        on the table. A task whose boxes go elsewhere (a slot, a shelf, a table per kind)
        overrides this, and the approach, the carry and the placing follow it."""
        zone = world.zone
        return Placement(zone.center, zone.rest_z)

    # --- phases ------------------------------------------------------------------------------

    def _wait(self, world: World) -> BaseTwist:
        c = world.config.conveyor
        standby = np.array([c.end_x + STANDBY_DISTANCE, c.center_y, c.direction_yaw + math.pi])
        self._ready_arms(world)
        box = self._resting_box(world)
        if box is None:
            self._noticed_at = None
        elif self._noticed_at is None:
            self._noticed_at = world.time
        elif world.time - self._noticed_at >= self.profile.reaction_s:
            self._box = box
            self._noticed_at = None
            self._enter(world, ExpertPhase.APPROACH)
        return self._drive(world, standby)

    def _pick_heading(self, world: World) -> float:
        """The base's heading while it picks a box: facing the belt by default."""
        return world.config.conveyor.direction_yaw + math.pi

    def _approach(self, world: World) -> BaseTwist:
        box = self._require_box()
        pos = world.boxes.position(world.data, box)
        heading = self._pick_heading(world)
        p = self.profile
        back = np.array([math.cos(heading), math.sin(heading)])
        side = np.array([-back[1], back[0]])
        goal_xy = pos[:2] - back * p.pick_distance_m + side * p.lateral_offset_m
        goal = np.array([goal_xy[0], goal_xy[1], heading])
        self._ready_arms(world)
        twist = self._drive(world, goal)
        if self._arrived(world, goal):
            self._enter(world, ExpertPhase.PREGRASP)
        return twist

    def _pregrasp(self, world: World) -> BaseTwist:
        self._palms = self._around_box(world, PREGRASP_GAP)
        self._close = 0.0
        if self._hands_at(world, self._palms) or self._timed_out(world):
            self._enter(world, ExpertPhase.GRASP)
        return BaseTwist()

    def _grasp(self, world: World) -> BaseTwist:
        box = self._require_box()
        self._palms = self._around_box(world, -SQUEEZE[world.config.grasp])
        if self._hands_at(world, self._palms, tolerance=0.03):
            self._close = 1.0
        if world.grasp.holding is box and world.time - self._phase_start > 0.4:
            self._enter(world, ExpertPhase.LIFT)
        elif self._timed_out(world, 4.0):
            self._grasp_attempts += 1
            self._close = 0.0
            self._enter(
                world, ExpertPhase.PREGRASP if self._grasp_attempts < 3 else ExpertPhase.BACKOFF
            )
        return BaseTwist()

    def _lift(self, world: World) -> BaseTwist:
        assert self._palms is not None
        if world.time - self._phase_start < 0.05:
            self._palms = self._palms.shifted(np.array([-0.05, 0.0, LIFT]))
        if self._lost_box(world):
            return BaseTwist()
        if self._hands_at(world, self._palms, tolerance=0.03) or self._timed_out(world, 3.0):
            self._enter(world, ExpertPhase.RETREAT)
        return BaseTwist()

    def _retreat(self, world: World) -> BaseTwist:
        pose = world.base_pose
        if not self._waypoints:
            back = np.array([math.cos(pose[2]), math.sin(pose[2])])
            goal = pose.copy()
            goal[:2] -= back * RETREAT_DISTANCE
            self._waypoints = [goal]
        if self._lost_box(world):
            return BaseTwist()
        goal = self._waypoints[0]
        twist = self._drive(world, goal, tolerance=0.05)
        if self._arrived(world, goal, tolerance=0.05):
            self._waypoints = self._carry_route(world)
            self._enter(world, ExpertPhase.CARRY)
        return twist

    def _carry(self, world: World) -> BaseTwist:
        if self._lost_box(world):
            return BaseTwist()
        goal = self._waypoints[0]
        last = len(self._waypoints) == 1
        tolerance = ARRIVED_M if last else 0.1
        twist = self._drive(world, goal, tolerance=tolerance)
        if self._arrived(world, goal, tolerance=tolerance):
            self._waypoints.pop(0)
            if not self._waypoints:
                self._enter(world, ExpertPhase.PLACE)
        return twist

    def _place(self, world: World) -> BaseTwist:
        box = self._require_box()
        assert self._palms is not None
        place = self.placement(world, box)
        if world.grasp.holding is not box:
            # Set down early (a pad slipped as the box met the table): let go right here.
            self._enter(world, ExpertPhase.RELEASE)
            return BaseTwist()
        center = world.to_base_frame(np.array([*place.center, place.rest_z + 0.012]))
        held = world.to_base_frame(world.boxes.position(world.data, box))
        reach = np.array([min(center[0], ARM_REACH + 0.05), center[1], center[2]])
        palms_center = (self._palms.left_position + self._palms.right_position) / 2
        # Move the palms so the box centre lands on the goal (palm centre and box centre
        # differ by how the box sits in the hands).
        goal_center = palms_center + (reach - held)
        delta = goal_center - palms_center
        step = np.clip(delta, -0.004, 0.004)
        self._palms = self._palms.shifted(step)
        settled = float(np.linalg.norm(delta)) < 0.01
        if settled or self._timed_out(world, 8.0):
            self._enter(world, ExpertPhase.RELEASE)
        return BaseTwist()

    def _release(self, world: World) -> BaseTwist:
        self._close = 0.0
        if world.time - self._phase_start > 0.3:
            self._palms = self._around_box(world, RELEASE_GAP, lift=0.02)
        if world.time - self._phase_start > 1.2:
            box = self._require_box()
            if box.state is BoxState.DELIVERED:
                self.deliveries += 1
            self._enter(world, ExpertPhase.BACKOFF)
        return BaseTwist()

    def _backoff(self, world: World) -> BaseTwist:
        self._close = 0.0
        pose = world.base_pose
        if not self._waypoints:
            back = np.array([math.cos(pose[2]), math.sin(pose[2])])
            goal = pose.copy()
            goal[:2] -= back * 0.4
            self._waypoints = [goal]
        if self._palms is not None:
            self._palms = self._palms.shifted(np.array([0.0, 0.0, 0.004]))
        goal = self._waypoints[0]
        twist = self._drive(world, goal, tolerance=0.05)
        if self._arrived(world, goal, tolerance=0.05) or self._timed_out(world, 5.0):
            self._waypoints = []
            self._box = None
            self._grasp_attempts = 0
            self._enter(world, ExpertPhase.WAIT)
        return twist

    # --- helpers -----------------------------------------------------------------------------

    def _enter(self, world: World, phase: ExpertPhase) -> None:
        self.phase = phase
        self._phase_start = world.time
        p = self.profile
        if p.hesitation_probability > 0 and self._rng.random() < p.hesitation_probability:
            self._pause_until = world.time + float(self._rng.uniform(0.0, p.max_hesitation_s))
        if (
            phase is not ExpertPhase.RETREAT
            and phase is not ExpertPhase.CARRY
            and phase is not ExpertPhase.BACKOFF
        ):
            self._waypoints = [] if phase is not ExpertPhase.PLACE else self._waypoints

    def _timed_out(self, world: World, limit: float = PHASE_TIMEOUT_S) -> bool:
        return world.time - self._phase_start > limit

    def _require_box(self) -> BoxSlot:
        if self._box is None:
            raise RuntimeError("the expert lost track of its box")
        return self._box

    def _lost_box(self, world: World) -> bool:
        """Dropped: give up on this box and go back to waiting for the next one."""
        if world.grasp.holding is self._box:
            return False
        self._close = 0.0
        self._waypoints = []
        self._enter(world, ExpertPhase.BACKOFF)
        return True

    def _resting_box(self, world: World) -> BoxSlot | None:
        c = world.config.conveyor
        best: BoxSlot | None = None
        for slot in world.boxes.active():
            pos = world.boxes.position(world.data, slot)
            on_belt = abs(pos[2] - (c.height + world.boxes.size_of(slot)[2] / 2)) < 0.03
            settled = world.time - slot.released_at > 1.0
            still = world.boxes.speed(world.data, slot) < REST_SPEED
            ahead = best is None or pos[0] > world.boxes.position(world.data, best)[0]
            if on_belt and settled and still and ahead:
                best = slot
        return best

    def _around_box(self, world: World, gap: float, lift: float = 0.0) -> PalmTargets:
        box = self._require_box()
        center = world.to_base_frame(world.boxes.position(world.data, box))
        center[2] += lift
        quat = world.boxes.quaternion(world.data, box)
        box_yaw = 2 * math.atan2(quat[3], quat[0])
        grasp_yaw = box_yaw + math.pi / 2 - float(world.base_pose[2])
        half = world.boxes.size_of(box)[1] / 2
        return palm_targets(center, grasp_yaw, half, gap)

    def _ready_arms(self, world: World) -> None:
        """Palms up and apart in front of the robot, clear of any box."""
        if self._ready is None:
            half = world.conditions.box_size[1] / 2
            center = np.array([0.5, 0.0, world.config.conveyor.height + 0.3])
            self._ready = palm_targets(center, math.pi / 2, half, 0.1)
        self._palms = self._ready
        self._close = 0.0

    def _hands_at(
        self, world: World, palms: PalmTargets, tolerance: float = HAND_TOLERANCE_M
    ) -> bool:
        left = world.to_base_frame(world.tcp_pose("l")[0])
        right = world.to_base_frame(world.tcp_pose("r")[0])
        return bool(
            np.linalg.norm(left - palms.left_position) < tolerance
            and np.linalg.norm(right - palms.right_position) < tolerance
        )

    def _carry_route(self, world: World) -> list[NDArray[np.float64]]:
        pose = world.base_pose
        p = self.profile
        place_center = self.placement(world, self._require_box()).center + np.array(p.place_offset)
        # Face the table square-on from the side the robot is coming from.
        to_table = place_center - pose[:2]
        if abs(to_table[0]) > abs(to_table[1]):
            heading = 0.0 if to_table[0] > 0 else math.pi
        else:
            heading = math.pi / 2 if to_table[1] > 0 else -math.pi / 2
        heading = pose[2] + wrap_angle(heading - pose[2])
        goal = np.array(
            [
                place_center[0] - self.place_distance * math.cos(heading),
                place_center[1] - self.place_distance * math.sin(heading),
                heading,
            ]
        )
        route: list[NDArray[np.float64]] = []
        if p.detour_m > 0.05:
            mid = (pose + goal) / 2
            normal = np.array([-math.sin(heading), math.cos(heading)])
            mid[:2] += normal * p.detour_m * float(self._rng.choice([-1.0, 1.0]))
            mid[2] = heading
            route.append(mid)
        route.append(goal)
        return route

    def _drive(
        self, world: World, goal: NDArray[np.float64], tolerance: float = ARRIVED_M
    ) -> BaseTwist:
        """A saturated proportional twist toward ``goal`` (x, y, yaw in the world)."""
        return twist_toward(world, goal, self.profile.speed_scale, tolerance)

    def _arrived(
        self, world: World, goal: NDArray[np.float64], tolerance: float = ARRIVED_M
    ) -> bool:
        return arrived_at(world, goal, tolerance)

    def _command(self, world: World, twist: BaseTwist) -> Command:
        palms = self._palms
        if palms is None:
            return Command(base=twist)
        tremor = self._tremor(world.time)
        return Command(
            base=twist,
            left=ArmCommand(
                tuple(palms.left_position + tremor), tuple(palms.left_quaternion), True
            ),
            right=ArmCommand(
                tuple(palms.right_position + tremor), tuple(palms.right_quaternion), True
            ),
            close_left=self._close,
            close_right=self._close,
        )

    def _tremor(self, t: float) -> NDArray[np.float64]:
        amplitude = self.profile.tremor_m
        if amplitude <= 0:
            return np.zeros(3)
        return amplitude * np.array(
            [math.sin(2.1 * t), math.sin(1.7 * t + 1.0), 0.5 * math.sin(2.9 * t + 2.0)]
        )

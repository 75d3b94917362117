"""The teleoperation operator: the latest raw input of a browser client → one Command.

The server's socket task calls :meth:`TeleopOperator.submit` whenever an
:class:`~workcell.protocol.messages.Input` arrives; the simulation thread calls
:meth:`act` once per control period with whatever input is newest (inputs are never
queued). :meth:`operator_input` gives the recorder the raw state behind each frame.
"""

from __future__ import annotations

import functools
import math
import threading
import time
from collections.abc import Callable

from workcell.control.command import BaseTwist, Command
from workcell.protocol.messages import Input
from workcell.recording.frame_capture import OperatorInput
from workcell.sim.world import World
from workcell.teleop.clutch import ArmClutch, Pose
from workcell.teleop.config import TeleopConfig
from workcell.teleop.mapping import base_twist, head_angles
from workcell.teleop.one_euro import PoseFilter
from workcell.teleop.rotation import conjugate, multiply
from workcell.teleop.snap_turn import SnapTurn
from workcell.teleop.soft_stop import SoftStop

TcpSource = Callable[[World, str], Pose]
"""Where an arm's TCP target is now (base frame), read when its grip engages."""
HeadingSource = Callable[[World], tuple[float, float]]
"""The base's reference heading and its yaw rate (rad, rad/s), which snap turns steer."""


def measured_heading(world: World) -> tuple[float, float]:
    """The base's measured heading and yaw rate (a moment behind its reference)."""
    return float(world.base_pose[2]), float(world.base_velocity[2])


def measured_tcp(world: World, side: str) -> Pose:
    """The measured TCP pose of one arm in the base frame."""
    position, quat = world.tcp_pose(side)
    x, y, z = (float(v) for v in world.to_base_frame(position))
    yaw = float(world.base_pose[2])
    heading = (math.cos(yaw / 2), 0.0, 0.0, math.sin(yaw / 2))
    w, qx, qy, qz = multiply(conjugate(heading), (quat[0], quat[1], quat[2], quat[3]))
    return (x, y, z, w, qx, qy, qz)


class TeleopOperator:
    """Implements the task's Operator protocol for a human at a browser."""

    def __init__(
        self,
        config: TeleopConfig,
        tcp_source: TcpSource = measured_tcp,
        clock: Callable[[], float] = time.monotonic,
        soft_stop: SoftStop | None = None,
        heading_source: HeadingSource = measured_heading,
    ) -> None:
        self.config = config
        self.soft_stop = soft_stop
        self._heading = heading_source
        """Slows the base before fixed obstacles (None: the sticks' twist as it is)."""
        self._tcp_source = tcp_source
        self.tcp_source = tcp_source
        """Where an arm's TCP target is now (base frame)."""
        self._clock = clock
        self._lock = threading.Lock()
        self._latest: Input | None = None
        self._arrived = 0.0
        self._last_seq = -1
        self._grippers = (0.0, 0.0)
        self.clutches = {side: ArmClutch(config.motion_scale) for side in ("l", "r")}
        self.applied_seq = -1
        """The sequence number of the input behind the latest command (-1: none yet)."""
        self._snap_asked = 0
        self.snap: SnapTurn | None = None
        """The snap turn under way, which drives the base's yaw instead of the stick."""
        settings = config.input
        self._filters = (
            tuple(
                PoseFilter(
                    settings.min_cutoff_hz,
                    settings.beta_position,
                    settings.beta_rotation,
                    settings.d_cutoff_hz,
                )
                for _ in range(3)
            )
            if settings.filter == "one_euro"
            else None
        )
        """One-Euro filters of the left hand, the right hand and the headset (None: off)."""
        self._poses: tuple[Pose | None, Pose | None, Pose | None] = (None, None, None)
        """The newest input's left, right and headset poses, filtered."""

    # --- the socket side --------------------------------------------------------------------

    def submit(self, message: Input) -> bool:
        """Make ``message`` the newest input; False (and ignored) when its ``seq`` is not
        newer than the last accepted one."""
        with self._lock:
            if message.seq <= self._last_seq:
                return False
            self._latest = message
            self._last_seq = message.seq
            self._arrived = self._clock()
            self._poses = self._filtered(message, self._arrived)
            return True

    def _filtered(self, message: Input, t: float) -> tuple[Pose | None, Pose | None, Pose | None]:
        raw = (message.left.pose, message.right.pose, message.headset)
        if self._filters is None:
            return raw
        poses: list[Pose | None] = []
        for pose, pose_filter in zip(raw, self._filters, strict=True):
            if pose is None:
                pose_filter.reset()  # tracking lost: start afresh when it returns
            poses.append(None if pose is None else pose_filter(t, pose))
        return poses[0], poses[1], poses[2]

    def new_link(self) -> None:
        """A (re)connected client numbers its inputs afresh (and its poses start afresh)."""
        with self._lock:
            self._last_seq = -1
            for pose_filter in self._filters or ():
                pose_filter.reset()

    # --- the Operator protocol --------------------------------------------------------------

    def start_trial(self, trial_seed: int) -> None:
        """The world was reset: forget the arm targets (grips must be pressed again) and
        any snap turn."""
        for clutch in self.clutches.values():
            clutch.reset()
        self._grippers = (0.0, 0.0)
        self._snap_asked = 0
        self.snap = None

    def after_pause(self) -> None:
        """The session resumes after a pause: each gripped arm re-anchors where it is
        (:meth:`~workcell.teleop.clutch.ArmClutch.reanchor`); on the simulation thread."""
        for clutch in self.clutches.values():
            clutch.reanchor()

    def ask_snap(self, direction: int) -> None:
        """Turn the base by :data:`~workcell.teleop.snap_turn.SNAP_ANGLE` (+1: left, -1:
        right), starting at the next control period (on the simulation thread)."""
        self._snap_asked = direction

    def act(self, world: World) -> Command:
        with self._lock:
            latest, arrived, poses = self._latest, self._arrived, self._poses
        age = self._clock() - arrived
        if latest is None or age > self.config.input_timeout_s:
            # No or stale input: stop the base, freeze the arms, keep the grippers; a held
            # grip stays engaged through a short gap (clutch_hold_s), so none of the hand's
            # motion during the gap is lost when input returns.
            self.snap = None  # no input: the base stops, a snap too
            hold = latest is not None and age <= self.config.clutch_hold_s
            arms = {
                side: clutch.hold() if hold else clutch.release()
                for side, clutch in self.clutches.items()
            }
            head = self.config.default_head if latest is None else self._head(poses[2])
            return Command(
                left=arms["l"],
                right=arms["r"],
                close_left=self._grippers[0],
                close_right=self._grippers[1],
                head=head,
            )
        self.applied_seq = latest.seq
        threshold = self.config.grip_threshold
        arms = {
            side: self.clutches[side].update(
                hand.grip >= threshold, pose, functools.partial(self._tcp_source, world, side)
            )
            for side, hand, pose in (("l", latest.left, poses[0]), ("r", latest.right, poses[1]))
        }
        self._grippers = (_unit(latest.left.trigger), _unit(latest.right.trigger))
        base = self._snapping(world, base_twist(latest.left.stick, latest.right.stick, self.config))
        if self.soft_stop is not None:
            base = self.soft_stop.limit(base, world.model, world.data, float(world.base_pose[2]))
        return Command(
            base=base,
            left=arms["l"],
            right=arms["r"],
            close_left=self._grippers[0],
            close_right=self._grippers[1],
            head=self._head(poses[2]),
        )

    def _snapping(self, world: World, base: BaseTwist) -> BaseTwist:
        """``base`` with its yaw rate from the snap turn under way, if any."""
        if not self._snap_asked and self.snap is None:
            return base
        yaw, yaw_rate = self._heading(world)
        if self._snap_asked:
            self.snap = SnapTurn(self._snap_asked, yaw)
            self._snap_asked = 0
        assert self.snap is not None
        rate = self.snap.yaw_rate(yaw, yaw_rate, self.config.max_yaw_rate, self.config.yaw_accel)
        if rate is None:
            self.snap = None
            return base
        return BaseTwist(vx=base.vx, vy=base.vy, wz=rate)

    def _head(self, headset: Pose | None) -> tuple[float, float]:
        quat = headset[3:] if headset is not None else None
        return head_angles(quat, self.config)

    # --- for the recorder -------------------------------------------------------------------

    def operator_input(self) -> OperatorInput | None:
        """The newest raw input as the recorder stores it, with the poses the arms and
        the view act on (filtered); None before any input."""
        with self._lock:
            latest, arrived, poses = self._latest, self._arrived, self._poses
        if latest is None:
            return None
        left, right = latest.left, latest.right
        return OperatorInput(
            grip=(left.grip, right.grip),
            trigger=(left.trigger, right.trigger),
            controller_l=left.pose,
            controller_r=right.pose,
            headset=latest.headset,
            stick_l=left.stick,
            stick_r=right.stick,
            buttons=(left.buttons, right.buttons),
            age_s=self._clock() - arrived,
            filtered_l=poses[0],
            filtered_r=poses[1],
            filtered_headset=poses[2],
        )


def _unit(value: float) -> float:
    return min(1.0, max(0.0, value))

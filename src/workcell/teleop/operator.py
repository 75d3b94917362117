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

from workcell.control.command import Command
from workcell.protocol.messages import Input
from workcell.recording.frame_capture import OperatorInput
from workcell.sim.world import World
from workcell.teleop.clutch import ArmClutch, Pose
from workcell.teleop.config import TeleopConfig
from workcell.teleop.mapping import base_twist, head_angles
from workcell.teleop.rotation import conjugate, multiply
from workcell.teleop.soft_stop import SoftStop

TcpSource = Callable[[World, str], Pose]
"""Where an arm's TCP target is now (base frame), read when its grip engages."""


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
    ) -> None:
        self.config = config
        self.soft_stop = soft_stop
        """Slows the base before fixed obstacles (None: the sticks' twist as it is)."""
        self._tcp_source = tcp_source
        self._clock = clock
        self._lock = threading.Lock()
        self._latest: Input | None = None
        self._arrived = 0.0
        self._last_seq = -1
        self._grippers = (0.0, 0.0)
        self.clutches = {side: ArmClutch(config.motion_scale) for side in ("l", "r")}
        self.applied_seq = -1
        """The sequence number of the input behind the latest command (-1: none yet)."""

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
            return True

    def new_link(self) -> None:
        """A (re)connected client numbers its inputs afresh."""
        with self._lock:
            self._last_seq = -1

    # --- the Operator protocol --------------------------------------------------------------

    def start_trial(self, trial_seed: int) -> None:
        """The world was reset: forget the arm targets (grips must be pressed again)."""
        for clutch in self.clutches.values():
            clutch.reset()
        self._grippers = (0.0, 0.0)

    def act(self, world: World) -> Command:
        with self._lock:
            latest, arrived = self._latest, self._arrived
        age = self._clock() - arrived
        if latest is None or age > self.config.input_timeout_s:
            # No or stale input: stop the base, freeze the arms, keep the grippers; a held
            # grip stays engaged through a short gap (clutch_hold_s), so none of the hand's
            # motion during the gap is lost when input returns.
            hold = latest is not None and age <= self.config.clutch_hold_s
            arms = {
                side: clutch.hold() if hold else clutch.release()
                for side, clutch in self.clutches.items()
            }
            head = self.config.default_head if latest is None else self._head(latest)
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
                hand.grip >= threshold, hand.pose, functools.partial(self._tcp_source, world, side)
            )
            for side, hand in (("l", latest.left), ("r", latest.right))
        }
        self._grippers = (_unit(latest.left.trigger), _unit(latest.right.trigger))
        base = base_twist(latest.left.stick, latest.right.stick, self.config)
        if self.soft_stop is not None:
            base = self.soft_stop.limit(base, world.model, world.data, float(world.base_pose[2]))
        return Command(
            base=base,
            left=arms["l"],
            right=arms["r"],
            close_left=self._grippers[0],
            close_right=self._grippers[1],
            head=self._head(latest),
        )

    def _head(self, latest: Input) -> tuple[float, float]:
        quat = latest.headset[3:] if latest.headset is not None else None
        return head_angles(quat, self.config)

    # --- for the recorder -------------------------------------------------------------------

    def operator_input(self) -> OperatorInput | None:
        """The newest raw input as the recorder stores it; None before any input."""
        with self._lock:
            latest, arrived = self._latest, self._arrived
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
        )


def _unit(value: float) -> float:
    return min(1.0, max(0.0, value))

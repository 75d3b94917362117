"""Clutch (relative) mapping from one controller to one arm's TCP target.

At engage the controller pose and the arm's current TCP target are remembered; while the
grip is held, the target is the engaged target moved by the controller's displacement
since engage and turned by its rotation since engage, both carried from the XR frame into
the base frame. Release freezes the target. Re-engaging anchors afresh, so the arm never
jumps: only motion made while holding the grip moves it. Lost tracking while held freezes
the target until the controller is seen again, then anchors afresh.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from workcell.control.command import ArmCommand
from workcell.teleop.rotation import (
    Quat,
    Vec3,
    conjugate,
    multiply,
    normalize,
    xr_to_base_rotation,
    xr_to_base_vector,
)

Pose = tuple[float, float, float, float, float, float, float]
RELEASED = ArmCommand()
"""An arm that never had a target: not followed."""


@dataclass(frozen=True)
class Anchor:
    """What was remembered at engage: the controller (XR frame) and the target (base)."""

    controller_position: Vec3
    controller_quat: Quat
    target_position: Vec3
    target_quat: Quat


def split(pose: Pose) -> tuple[Vec3, Quat]:
    return (pose[0], pose[1], pose[2]), (pose[3], pose[4], pose[5], pose[6])


class ArmClutch:
    """One arm's clutch state; :meth:`update` once per control step."""

    def __init__(self, motion_scale: float = 1.0) -> None:
        self.motion_scale = motion_scale
        self.anchor: Anchor | None = None
        self.target: Pose | None = None
        """The latest target (base frame): followed while engaged, frozen after."""
        self._released: tuple[Pose | None, ArmCommand] = (None, RELEASED)
        """The command of a released arm and the target it was made for: a released arm
        sends the same command every period, made (and checked) once."""

    def reset(self) -> None:
        self.anchor = None
        self.target = None

    @property
    def engaged(self) -> bool:
        return self.anchor is not None

    def update(
        self, held: bool, controller: Pose | None, current_target: Callable[[], Pose]
    ) -> ArmCommand:
        """The arm command for this step. ``current_target()`` says where the arm's TCP
        target is now (base frame); it is called only at engage."""
        if not held or controller is None:
            return self.release()
        position, quat = split(controller)
        if self.anchor is None:
            target_position, target_quat = split(current_target())
            self.anchor = Anchor(position, normalize(quat), target_position, target_quat)
        self.target = self._follow(self.anchor, position, quat)
        return ArmCommand(position=self.target[:3], quaternion=self.target[3:], follow=True)

    def _follow(self, anchor: Anchor, position: Vec3, quat: Quat) -> Pose:
        delta = tuple(
            (now - then) * self.motion_scale
            for now, then in zip(position, anchor.controller_position, strict=True)
        )
        moved = xr_to_base_vector((delta[0], delta[1], delta[2]))
        x, y, z = (t + d for t, d in zip(anchor.target_position, moved, strict=True))
        relative_xr = multiply(normalize(quat), conjugate(anchor.controller_quat))
        turned = normalize(multiply(xr_to_base_rotation(relative_xr), anchor.target_quat))
        return (x, y, z, *turned)

    def reanchor(self) -> None:
        """Forget where the hand was when it gripped, keeping the target: a grip still held
        engages afresh at the next update, where the arm is, so a hand that moved meanwhile
        (the session stood paused) does not jump the arm."""
        self.anchor = None

    def hold(self) -> ArmCommand:
        """Input stalled with the grip held: stay engaged (the anchor is kept, so the arm
        follows on from it when input returns) and wait at the current target."""
        if self.anchor is None or self.target is None:
            return self.release()
        return ArmCommand(position=self.target[:3], quaternion=self.target[3:], follow=True)

    def release(self) -> ArmCommand:
        """Let go (or stay let go): the target stays where it is and is not followed."""
        self.anchor = None
        target, command = self._released
        if target is not self.target:
            command = RELEASED
            if self.target is not None:
                command = ArmCommand(self.target[:3], self.target[3:], follow=False)
            self._released = (self.target, command)
        return command

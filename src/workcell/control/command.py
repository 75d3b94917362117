"""The one way anything drives the robot.

Every operator (VR, desktop, scripted expert, replay) produces :class:`Command` values and
nothing else, so all of them run through the same controller and are recorded alike.
Arm targets are TCP poses in the base frame (x forward, y left, z up, origin on the floor
under the base centre), so a held arm pose travels with the base.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from workcell.errors import WorkcellError

QUATERNION_NORM_TOLERANCE = 1e-2
"""How far from 1 a target quaternion's norm may be (float32 headsets land well inside)."""

Vec3 = tuple[float, float, float]
Quat = tuple[float, float, float, float]


class CommandError(WorkcellError):
    """A command carried a non-finite or out-of-range value."""


def _require_finite(name: str, values: tuple[float, ...]) -> None:
    if not all(map(math.isfinite, values)):
        raise CommandError(f"{name} = {values}: every component must be a finite number")


@dataclass(frozen=True)
class BaseTwist:
    """Base velocity in the base frame: m/s forward and left, rad/s counter-clockwise."""

    vx: float = 0.0
    vy: float = 0.0
    wz: float = 0.0

    def __post_init__(self) -> None:
        _require_finite("base twist", (self.vx, self.vy, self.wz))


@dataclass(frozen=True)
class ArmCommand:
    """A TCP target pose in the base frame; the arm tracks it only while ``follow``."""

    position: Vec3 = (0.0, 0.0, 0.0)
    quaternion: Quat = (1.0, 0.0, 0.0, 0.0)
    follow: bool = False

    def __post_init__(self) -> None:
        _require_finite("arm target position", self.position)
        _require_finite("arm target quaternion", self.quaternion)
        norm = math.sqrt(sum(q * q for q in self.quaternion))
        if abs(norm - 1.0) > QUATERNION_NORM_TOLERANCE:
            raise CommandError(
                f"arm target quaternion = {self.quaternion}: must be a unit quaternion "
                f"(w, x, y, z) within {QUATERNION_NORM_TOLERANCE:g}; its norm is {norm:.6g}"
            )


@dataclass(frozen=True)
class Command:
    """Base twist, both arms, both grippers and the head (pan, tilt).

    ``close_left`` / ``close_right`` say how far each gripper is commanded closed, 0 open ..
    1 closed (the trigger); frames record them as ``gripper_cmd_l`` / ``gripper_cmd_r``.
    The measured finger opening, ``gripper_l`` / ``gripper_r``, runs the other way: 1 open.

    ``base_push`` is not the operator's: a disturbance added to its base twist before the
    controller executes it (:attr:`executed_base`), set only by the pushed expert
    (:mod:`workcell.expert.noise`). Frames record ``base``, what the operator asked for
    (``cmd_vx``, ``cmd_vy``, ``cmd_wz``), as DART records the expert's own action.
    """

    base: BaseTwist = field(default_factory=BaseTwist)
    left: ArmCommand = field(default_factory=ArmCommand)
    right: ArmCommand = field(default_factory=ArmCommand)
    close_left: float = 0.0
    close_right: float = 0.0
    head: tuple[float, float] = (0.0, 0.3)
    base_push: BaseTwist | None = None

    @property
    def executed_base(self) -> BaseTwist:
        """The base twist the controller executes: ``base`` plus ``base_push``, if any."""
        push = self.base_push
        if push is None:  # every operator but the pushed expert: nothing to build
            return self.base
        base = self.base
        return BaseTwist(base.vx + push.vx, base.vy + push.vy, base.wz + push.wz)

    def __post_init__(self) -> None:
        for name, value in (
            ("close_left", self.close_left),
            ("close_right", self.close_right),
        ):
            if not (math.isfinite(value) and 0.0 <= value <= 1.0):
                raise CommandError(f"{name} = {value}: must be between 0 (open) and 1 (closed)")
        _require_finite("head", self.head)

"""The robot's 17-joint order: defined here and nowhere else, written into every manifest.

Radians for hinges, metres for the spine. The base pose (x, y, yaw) is recorded apart.
"""

from __future__ import annotations

ARM_JOINTS_PER_SIDE = 7
SIDES: tuple[str, str] = ("l", "r")

SPINE_JOINT = "spine"
HEAD_JOINTS: tuple[str, str] = ("head_pan", "head_tilt")


def arm_joint_names(side: str) -> tuple[str, ...]:
    """Joint names of one arm, shoulder to wrist: ``arm_l_1`` .. ``arm_l_7``."""
    return tuple(f"arm_{side}_{i}" for i in range(1, ARM_JOINTS_PER_SIDE + 1))


JOINT_ORDER: tuple[str, ...] = (
    SPINE_JOINT,
    *HEAD_JOINTS,
    *arm_joint_names("l"),
    *arm_joint_names("r"),
)
"""spine (1), head pan and tilt (2), left arm (7), right arm (7)."""

BASE_JOINTS: tuple[str, str, str] = ("base_x", "base_y", "base_yaw")
FINGER_JOINTS: dict[str, tuple[str, str]] = {
    side: (f"finger_{side}_a", f"finger_{side}_b") for side in SIDES
}

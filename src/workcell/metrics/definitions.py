"""What every metric means: version, thresholds and plain-English definitions.

These are written into every manifest and report, so a reader can recompute each value
from ``frames.csv`` alone (DESIGN.md "Metrics"). Units: metres, seconds, radians.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from workcell.checks import problem
from workcell.errors import ConfigError

METRICS_VERSION = "1"
"""Bumped whenever a definition below changes meaning."""


def _positive(field: str, value: object, unit: str) -> list[str]:
    if isinstance(value, bool) or not isinstance(value, int | float):
        return [problem(field, value, "must be a number")]
    if not math.isfinite(value) or value <= 0:
        return [problem(field, value, f"must be a finite number > 0 {unit}")]
    return []


@dataclass(frozen=True)
class MetricThresholds:
    """Thresholds that decide when a grip is active and when the robot moves.

    ``grip_threshold`` is a grip button value (0-1, active when the value is >= it);
    ``base_linear_mps`` m/s, ``base_yaw_radps`` rad/s and ``joint_rate_radps`` rad/s are
    speeds that must be strictly exceeded to count as motion.
    """

    grip_threshold: float = 0.5
    base_linear_mps: float = 0.02
    base_yaw_radps: float = 0.05
    joint_rate_radps: float = 0.05

    def __post_init__(self) -> None:
        problems: list[str] = []
        grip = self.grip_threshold
        if isinstance(grip, bool) or not isinstance(grip, int | float):
            problems.append(problem("grip_threshold", grip, "must be a number"))
        elif not (math.isfinite(grip) and 0 < grip <= 1):
            problems.append(problem("grip_threshold", grip, "must be between 0 and 1 (0 excluded)"))
        problems += _positive("base_linear_mps", self.base_linear_mps, "m/s")
        problems += _positive("base_yaw_radps", self.base_yaw_radps, "rad/s")
        problems += _positive("joint_rate_radps", self.joint_rate_radps, "rad/s")
        if problems:
            raise ConfigError(problems)


METRIC_DEFINITIONS: dict[str, str] = {
    "completion_time_s": (
        "Seconds: t_sim of the last frame of a successful trial (the delivery frame); "
        "empty for a trial that did not succeed or has no frames."
    ),
    "path_length_m": (
        "Metres: sum over consecutive frames t = 1..n-1 of the Euclidean distance "
        "||m_t - m_(t-1)||, where m_t = (p_L,t + p_R,t) / 2 is the midpoint of the left and "
        "right TCP positions (tcp_l_x/y/z, tcp_r_x/y/z) in the world frame; it covers base "
        "and arm motion. 0 for fewer than 2 frames; NaN if any TCP position is non-finite."
    ),
    "smoothness": (
        "rad/sample^2: mean of |q_j,t+1 - 2 q_j,t + q_j,t-1| over the 14 arm joints j "
        "(arm_l_1..7, arm_r_1..7) and every frame t = 1..n-2 at which that joint's arm has "
        "its grip active at t-1, t and t+1 (left arm gated by grip_l, right arm by grip_r; "
        "a grip is active when its value >= grip_threshold, so a non-finite grip is "
        "inactive). The terms of both arms are pooled into one mean. NaN if there is no "
        "such term, or if a counted term involves a non-finite joint position."
    ),
    "active_ratio": (
        "Share (0-1) of frames in which the base moves (sqrt(base_vx^2 + base_vy^2) > "
        "base_linear_mps or |base_wz| > base_yaw_radps) or an arm moves under grip "
        "(|dq_j| > joint_rate_radps for some arm joint j whose arm's grip is active in that "
        "frame). Non-finite speeds and grips count as not moving and not active. NaN for a "
        "trial with no frames."
    ),
    "hz_wall": (
        "Hz: (n - 1) / (t_wall of the last frame - t_wall of the first frame). NaN for "
        "fewer than 2 frames or a span that is not a finite number > 0."
    ),
    "hz_sim": (
        "Hz: (n - 1) / (t_sim of the last frame - t_sim of the first frame). NaN for "
        "fewer than 2 frames or a span that is not a finite number > 0."
    ),
    "max_gap_s": (
        "Seconds: largest difference t_wall,t - t_wall,t-1 between consecutive frames. "
        "0 for fewer than 2 frames; not finite (NaN or inf) if any t_wall is not finite."
    ),
    "nonfinite_share": (
        "Share (0-1) of frames holding at least one NaN or infinite value among t_sim, "
        "t_wall, base_vx/vy/wz, both TCP positions, the 14 arm joint positions and rates, "
        "grip_l and grip_r. NaN for a trial with no frames."
    ),
    "monotonic": (
        "True when both t_sim and t_wall strictly increase from every frame to the next "
        "(a NaN timestamp breaks it); true for fewer than 2 frames."
    ),
}
"""One definition per metric, keyed by its trials.csv / summary column name."""

AUDIT_ONLY_METRICS: tuple[str, ...] = ("nonfinite_share", "monotonic")
"""Metrics the audit computes and reports but a trial row does not store."""
STORED_METRICS: tuple[str, ...] = tuple(
    m for m in METRIC_DEFINITIONS if m not in AUDIT_ONLY_METRICS
)
"""The metrics stored on every trial row (trials.csv columns), in definition order."""
RECOMPUTED_COLUMNS: tuple[str, ...] = ("n_frames", *STORED_METRICS)
"""The trial columns that recomputing a trial's metrics from its frames yields: the frame
count and every stored metric (what the audit cross-checks and writes to its trials.csv)."""

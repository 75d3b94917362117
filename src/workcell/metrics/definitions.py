"""What every metric means: version, thresholds and plain-English definitions.

These are written into every manifest and report, so a reader can recompute each value
from ``frames.csv`` alone (docs/architecture.md "Metrics"). Units: metres, seconds, radians.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, fields
from typing import Any

from workcell.errors import ConfigError
from workcell.settings import declared_problems, setting

METRICS_VERSION = "1"
"""Bumped whenever a definition below changes meaning."""


@dataclass(frozen=True)
class MetricThresholds:
    """Thresholds that decide when a grip is active and when the robot moves.

    A grip is active when its value is at or above ``grip_threshold``; a speed counts as
    motion when it strictly exceeds its threshold. Declared here once; the session's
    ``recording`` settings take them over (:func:`workcell.settings.same_as`), and every
    session row stores them under these names.
    """

    grip_threshold: float = setting(
        0.5,
        "a grip value at or above this engages arm following",
        unit="1",
        low=0.0,
        low_open=True,
        high=1.0,
    )
    base_linear_threshold: float = setting(
        0.02,
        "base speed above which the base counts as moving",
        unit="m/s",
        low=0.0,
        low_open=True,
        high=1.0,
    )
    base_yaw_threshold: float = setting(
        0.05,
        "base turn rate above which the base counts as moving",
        unit="rad/s",
        low=0.0,
        low_open=True,
        high=1.0,
    )
    joint_rate_threshold: float = setting(
        0.05,
        "arm joint speed above which an arm counts as moving",
        unit="rad/s",
        low=0.0,
        low_open=True,
        high=1.0,
    )

    def __post_init__(self) -> None:
        problems = declared_problems(self, "")
        if problems:
            raise ConfigError(problems)

    @classmethod
    def from_stored(cls, stored: Mapping[str, Any]) -> MetricThresholds:
        """The thresholds of a session row's ``thresholds_json``. Older stores name three
        of them as :data:`LEGACY_THRESHOLD_NAMES` lists; they are read under their current
        names. Raises ValueError unless exactly the four thresholds are present."""
        renamed = {LEGACY_THRESHOLD_NAMES.get(key, key): value for key, value in stored.items()}
        expected = {f.name for f in fields(cls)}
        if len(renamed) != len(stored) or set(renamed) != expected:
            raise ValueError(f"keys {sorted(stored)} are not {sorted(expected)}")
        return cls(**renamed)


LEGACY_THRESHOLD_NAMES: dict[str, str] = {
    "base_linear_mps": "base_linear_threshold",
    "base_yaw_radps": "base_yaw_threshold",
    "joint_rate_radps": "joint_rate_threshold",
}
"""Threshold names in stores recorded before they matched the session settings
(``recording.base_linear_threshold`` and so on), and the names they have now."""


METRIC_DEFINITIONS: dict[str, str] = {
    "completion_time_s": (
        "Seconds: t_sim of the last frame of a successful trial (the frame its task was done); "
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
        "base_linear_threshold or |base_wz| > base_yaw_threshold) or an arm moves under grip "
        "(|dq_j| > joint_rate_threshold for some arm joint j whose arm's grip is active in that "
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

"""Thresholds are validated one line per problem; every metric has a definition."""

from __future__ import annotations

import math
from dataclasses import fields
from typing import Any

import pytest

from workcell.errors import ConfigError
from workcell.metrics import METRIC_DEFINITIONS, METRICS_VERSION, MetricThresholds
from workcell.record.columns import TRIAL_COLUMNS
from workcell.recording.recorder import metric_thresholds
from workcell.session.config import RecordingConfig, SessionConfig


def test_defaults_are_design_md_values() -> None:
    thresholds = MetricThresholds()
    assert thresholds.grip_threshold == 0.5
    assert thresholds.base_linear_threshold == 0.02
    assert thresholds.base_yaw_threshold == 0.05
    assert thresholds.joint_rate_threshold == 0.05
    assert METRICS_VERSION == "1"


def test_grip_threshold_of_one_is_allowed() -> None:
    assert MetricThresholds(grip_threshold=1.0).grip_threshold == 1.0


@pytest.mark.parametrize(
    ("field", "value", "line"),
    [
        ("grip_threshold", 1.5, "grip_threshold = 1.5: must be > 0 and at most 1"),
        ("grip_threshold", 0.0, "grip_threshold = 0: must be > 0 and at most 1"),
        ("grip_threshold", math.nan, "grip_threshold = nan: must be > 0 and at most 1"),
        ("grip_threshold", "high", "grip_threshold = 'high': must be > 0 and at most 1"),
        ("base_linear_threshold", 0.0, "base_linear_threshold = 0: must be > 0 and at most 1 m/s"),
        (
            "base_linear_threshold",
            math.inf,
            "base_linear_threshold = inf: must be > 0 and at most 1 m/s",
        ),
        ("base_yaw_threshold", -0.1, "base_yaw_threshold = -0.1: must be > 0 and at most 1 rad/s"),
        (
            "joint_rate_threshold",
            math.nan,
            "joint_rate_threshold = nan: must be > 0 and at most 1 rad/s",
        ),
        (
            "joint_rate_threshold",
            True,
            "joint_rate_threshold = True: must be > 0 and at most 1 rad/s",
        ),
    ],
)
def test_one_problem_names_field_value_and_rule(field: str, value: Any, line: str) -> None:
    with pytest.raises(ConfigError) as raised:
        MetricThresholds(**{field: value})
    assert raised.value.problems == (line,)


def test_every_problem_gets_its_own_line() -> None:
    with pytest.raises(ConfigError) as raised:
        MetricThresholds(grip_threshold=2.0, base_linear_threshold=-1.0, joint_rate_threshold=0.0)
    assert len(raised.value.problems) == 3
    assert str(raised.value).count("\n") == 2
    assert [p.split(" = ")[0] for p in raised.value.problems] == [
        "grip_threshold",
        "base_linear_threshold",
        "joint_rate_threshold",
    ]


def test_recording_settings_take_the_thresholds_over_by_name() -> None:
    recording = RecordingConfig()
    for threshold in fields(MetricThresholds):
        assert getattr(recording, threshold.name) == getattr(MetricThresholds(), threshold.name)
    tuned = RecordingConfig(base_yaw_threshold=0.2)
    assert metric_thresholds(SessionConfig(recording=tuned)).base_yaw_threshold == 0.2


def test_stored_thresholds_are_read_under_current_and_earlier_names() -> None:
    current = {"grip_threshold": 0.6, "base_linear_threshold": 0.03}
    current |= {"base_yaw_threshold": 0.07, "joint_rate_threshold": 0.08}
    earlier = {"grip_threshold": 0.6, "base_linear_mps": 0.03}
    earlier |= {"base_yaw_radps": 0.07, "joint_rate_radps": 0.08}
    expected = MetricThresholds(0.6, 0.03, 0.07, 0.08)
    assert MetricThresholds.from_stored(current) == expected
    assert MetricThresholds.from_stored(earlier) == expected
    with pytest.raises(ValueError, match="are not"):
        MetricThresholds.from_stored({**current, "base_linear_mps": 0.03})
    with pytest.raises(ValueError, match="are not"):
        MetricThresholds.from_stored({"grip_threshold": 0.6})


def test_definitions_cover_every_metric_column() -> None:
    metric_columns = TRIAL_COLUMNS[TRIAL_COLUMNS.index("path_length_m") : -3]
    assert metric_columns == (
        "path_length_m",
        "smoothness",
        "active_ratio",
        "hz_wall",
        "hz_sim",
        "max_gap_s",
    )
    expected = {"completion_time_s", *metric_columns, "nonfinite_share", "monotonic"}
    assert set(METRIC_DEFINITIONS) == expected
    assert all(len(text) > 40 for text in METRIC_DEFINITIONS.values())


def test_definitions_state_units_and_thresholds() -> None:
    assert "rad/sample^2" in METRIC_DEFINITIONS["smoothness"]
    assert ">= grip_threshold" in METRIC_DEFINITIONS["smoothness"]
    assert "pooled" in METRIC_DEFINITIONS["smoothness"]
    assert "> base_yaw_threshold" in METRIC_DEFINITIONS["active_ratio"]
    assert "> joint_rate_threshold" in METRIC_DEFINITIONS["active_ratio"]
    assert METRIC_DEFINITIONS["path_length_m"].startswith("Metres")

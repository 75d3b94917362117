"""Thresholds are validated one line per problem; every metric has a definition."""

from __future__ import annotations

import math
from typing import Any

import pytest

from workcell.errors import ConfigError
from workcell.metrics import METRIC_DEFINITIONS, METRICS_VERSION, MetricThresholds
from workcell.record.columns import TRIAL_COLUMNS


def test_defaults_are_design_md_values() -> None:
    thresholds = MetricThresholds()
    assert thresholds.grip_threshold == 0.5
    assert thresholds.base_linear_mps == 0.02
    assert thresholds.base_yaw_radps == 0.05
    assert thresholds.joint_rate_radps == 0.05
    assert METRICS_VERSION == "1"


def test_grip_threshold_of_one_is_allowed() -> None:
    assert MetricThresholds(grip_threshold=1.0).grip_threshold == 1.0


@pytest.mark.parametrize(
    ("field", "value", "line"),
    [
        ("grip_threshold", 1.5, "grip_threshold = 1.5: must be between 0 and 1 (0 excluded)"),
        ("grip_threshold", 0.0, "grip_threshold = 0: must be between 0 and 1 (0 excluded)"),
        ("grip_threshold", math.nan, "grip_threshold = nan: must be between 0 and 1 (0 excluded)"),
        ("grip_threshold", "high", "grip_threshold = 'high': must be a number"),
        ("base_linear_mps", 0.0, "base_linear_mps = 0: must be a finite number > 0 m/s"),
        ("base_linear_mps", math.inf, "base_linear_mps = inf: must be a finite number > 0 m/s"),
        ("base_yaw_radps", -0.1, "base_yaw_radps = -0.1: must be a finite number > 0 rad/s"),
        ("joint_rate_radps", math.nan, "joint_rate_radps = nan: must be a finite number > 0 rad/s"),
        ("joint_rate_radps", True, "joint_rate_radps = True: must be a number"),
    ],
)
def test_one_problem_names_field_value_and_rule(field: str, value: Any, line: str) -> None:
    with pytest.raises(ConfigError) as raised:
        MetricThresholds(**{field: value})
    assert raised.value.problems == (line,)


def test_every_problem_gets_its_own_line() -> None:
    with pytest.raises(ConfigError) as raised:
        MetricThresholds(grip_threshold=2.0, base_linear_mps=-1.0, joint_rate_radps=0.0)
    assert len(raised.value.problems) == 3
    assert str(raised.value).count("\n") == 2
    assert [p.split(" = ")[0] for p in raised.value.problems] == [
        "grip_threshold",
        "base_linear_mps",
        "joint_rate_radps",
    ]


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
    assert "> base_yaw_radps" in METRIC_DEFINITIONS["active_ratio"]
    assert "> joint_rate_radps" in METRIC_DEFINITIONS["active_ratio"]
    assert METRIC_DEFINITIONS["path_length_m"].startswith("Metres")

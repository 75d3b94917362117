"""Trial metrics and session statistics, recomputable from frames alone
(docs/architecture.md "Metrics").

Build :class:`FrameArrays` from one trial's frames.csv columns, then
:func:`compute_trial_metrics` with :class:`MetricThresholds`; summarise trials with
:func:`describe` and success counts with :func:`wilson_interval`. The definitions in
:data:`METRIC_DEFINITIONS` (version :data:`METRICS_VERSION`) go into every manifest.
"""

from __future__ import annotations

from workcell.errors import MetricsError
from workcell.metrics.definitions import METRIC_DEFINITIONS, METRICS_VERSION, MetricThresholds
from workcell.metrics.frames import REQUIRED_COLUMNS, FrameArrays
from workcell.metrics.statistics import Z_95, Descriptive, describe, wilson_interval
from workcell.metrics.trial import TrialMetrics, compute_trial_metrics

__all__ = [
    "METRICS_VERSION",
    "METRIC_DEFINITIONS",
    "REQUIRED_COLUMNS",
    "Z_95",
    "Descriptive",
    "FrameArrays",
    "MetricThresholds",
    "MetricsError",
    "TrialMetrics",
    "compute_trial_metrics",
    "describe",
    "wilson_interval",
]

"""The metric columns are derived from the metric definitions, and the CSV contract
(column names and order) stays exactly what docs/architecture.md publishes."""

from __future__ import annotations

from workcell.audit.crosscheck import CROSSCHECKED
from workcell.audit.trials_csv import AUDIT_COLUMNS
from workcell.metrics import TrialMetrics
from workcell.metrics.definitions import (
    AUDIT_ONLY_METRICS,
    METRIC_DEFINITIONS,
    RECOMPUTED_COLUMNS,
    STORED_METRICS,
)
from workcell.record.columns import TRIAL_COLUMNS

CONTRACT_TRIALS_CSV = (
    "session_id,trial_id,trial_index,mode,round,level,required_boxes,time_limit_s,outcome,"
    "interruption_reason,elapsed_s,completion_time_s,boxes_delivered,score,n_frames,"
    "path_length_m,smoothness,active_ratio,hz_wall,hz_sim,max_gap_s,quality_flags,included,"
    "exclusion_reason"
)


def test_trials_csv_header_is_the_contracts_exactly() -> None:
    assert ",".join(TRIAL_COLUMNS) == CONTRACT_TRIALS_CSV


def test_every_defined_metric_is_stored_or_reported_by_the_audit_only() -> None:
    assert set(STORED_METRICS) | set(AUDIT_ONLY_METRICS) == set(METRIC_DEFINITIONS)
    assert not set(STORED_METRICS) & set(AUDIT_ONLY_METRICS)
    assert set(STORED_METRICS) <= set(TRIAL_COLUMNS)
    assert not set(AUDIT_ONLY_METRICS) & set(TRIAL_COLUMNS)


def test_the_audit_checks_and_writes_what_the_definitions_store() -> None:
    assert CROSSCHECKED == RECOMPUTED_COLUMNS == ("n_frames", *STORED_METRICS)
    assert AUDIT_COLUMNS[: len(AUDIT_ONLY_METRICS)] == AUDIT_ONLY_METRICS
    computed = set(TrialMetrics.__dataclass_fields__)
    assert set(RECOMPUTED_COLUMNS) | set(AUDIT_ONLY_METRICS) <= computed

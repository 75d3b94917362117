"""trials.csv of an audit: the contract's trial columns, then every flag and disposition.

The contract's derived columns (n_frames, completion_time_s, the metrics) hold the values
recomputed from frames; ``quality_flags``, ``included`` and ``exclusion_reason`` the
audit's final decision. Cells are written as in a CSV export (reals with ``repr``, NULL
and NaN as an empty cell).
"""

from __future__ import annotations

import csv
import math
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from workcell.audit.flags import FLAG_NAMES
from workcell.audit.trial_audit import TrialAudit
from workcell.metrics.definitions import AUDIT_ONLY_METRICS, RECOMPUTED_COLUMNS
from workcell.record.columns import TRIAL_COLUMNS
from workcell.record.csv_format import format_row
from workcell.record.entries import FLAG_SEPARATOR
from workcell.record.study_tags import STUDY_COLUMNS

AUDIT_COLUMNS: tuple[str, ...] = (
    *AUDIT_ONLY_METRICS,
    *(f"flag_{name}" for name in FLAG_NAMES),
    "flag_details",
    "disposition",
    "marked",
    "automatic_included",
    "automatic_exclusion_reason",
    "review_kind",
    "review_by",
    "review_reason",
    "review_overridden",
    "review_refused",
    "stored_quality_flags",
    "stored_included",
    "metric_mismatches",
    "stage_reached",
    *STUDY_COLUMNS,
)
"""Columns after the contract's: flags 0/1, ``disposition`` one of STAGES, review fields
from the deciding annotation, what the trial row stored, mismatching metrics, how far the
trial got, and its session's study tags (:mod:`workcell.record.study_tags`: participant,
condition, study step; empty when there is none). New columns are added at the end."""

COLUMNS: tuple[str, ...] = TRIAL_COLUMNS + AUDIT_COLUMNS


def _cell(value: Any) -> Any:
    if isinstance(value, bool):
        return int(value)
    if isinstance(value, float) and math.isnan(value):
        return None
    return value


def trial_row(trial: TrialAudit) -> list[Any]:
    """One trial's cells in COLUMNS order (Python values; None is an empty cell)."""
    values = dict(trial.row.stored)
    for name in RECOMPUTED_COLUMNS:
        values[name] = getattr(trial.metrics, name)
    d = trial.disposition
    names = {f.name for f in trial.flags}
    review = d.review
    values |= {
        "quality_flags": FLAG_SEPARATOR.join(f.name for f in trial.flags) or None,
        "included": d.included,
        "exclusion_reason": d.exclusion_reason,
        **{name: getattr(trial.metrics, name) for name in AUDIT_ONLY_METRICS},
        **{f"flag_{name}": name in names for name in FLAG_NAMES},
        "flag_details": " | ".join(f"{f.name}: {f.detail}" for f in trial.flags) or None,
        "disposition": d.stage,
        "marked": d.marked,
        "automatic_included": d.automatic_included,
        "automatic_exclusion_reason": d.automatic_reason,
        "review_kind": review.kind if review else None,
        "review_by": review.by if review else None,
        "review_reason": review.reason if review else None,
        "review_overridden": d.overridden,
        "review_refused": d.refused,
        "stored_quality_flags": trial.row.stored["quality_flags"],
        "stored_included": trial.row.stored["included"],
        "metric_mismatches": FLAG_SEPARATOR.join(m.metric for m in trial.mismatches) or None,
        "stage_reached": trial.task_stage,
        "operator_id": trial.session.operator_id,
        "condition": trial.session.condition or None,
        "study_step": trial.session.study_step,
    }
    return [_cell(values[name]) for name in COLUMNS]


def write_trials_csv(path: Path, trials: Sequence[TrialAudit]) -> None:
    with path.open("w", newline="") as file:
        writer = csv.writer(file, lineterminator="\n")
        writer.writerow(COLUMNS)
        writer.writerows(format_row(trial_row(t)) for t in trials)

"""Detectors that judge a trial against the audited set: run once every trial is audited."""

from __future__ import annotations

import math
import statistics
from collections import defaultdict
from collections.abc import Collection, Sequence
from dataclasses import replace

from workcell.audit.disposition import decide
from workcell.audit.slowness import SlownessParams, detect_slow
from workcell.audit.trial_audit import TrialAudit

Task = tuple[str, str, object]


def _task(trial: TrialAudit) -> Task:
    return trial.task, trial.row.mode, trial.row.stored.get("required_boxes")


def flag_slow(
    trials: Sequence[TrialAudit], params: SlownessParams, taken_over: Collection[str] = ()
) -> list[TrialAudit]:
    """``trials`` in the given order, ``slow`` added to each success it applies to (and its
    disposition decided again with the flag); ``taken_over``: the ids of trials a person
    took over from an autonomous driver, neither flagged nor counted in a reference; see
    :mod:`workcell.audit.slowness`."""
    groups: dict[Task, list[float]] = defaultdict(list)
    for trial in trials:
        time = trial.metrics.completion_time_s
        if (
            trial.valid_success
            and trial.trial_id not in taken_over
            and time is not None
            and math.isfinite(time)
        ):
            groups[_task(trial)].append(time)
    result = []
    for trial in trials:
        times = groups.get(_task(trial), [])
        flag = None
        if (
            trial.row.outcome == "success"
            and trial.trial_id not in taken_over
            and len(times) >= params.min_reference
        ):
            flag = detect_slow(
                trial.metrics.completion_time_s, statistics.median(times), len(times), params
            )
        if flag is None:
            result.append(trial)
            continue
        flags = (*trial.flags, flag)
        disposition = decide(trial.row, flags, trial.disposition.review)
        result.append(replace(trial, flags=flags, disposition=disposition))
    return result

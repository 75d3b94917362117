"""Building audit test stores from real expert trials: copy, inject, truncate, tamper.

Frames are taken from a store a real ``workcell collect`` wrote and written into a new store
through the Store API, with the trial's metrics recomputed (as the recorder does) unless a
test asks for others.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from workcell.metrics import FrameArrays, MetricThresholds, compute_trial_metrics
from workcell.record import SessionInfo, SessionRecord, Store, StoredMetrics, TrialEnd, TrialStart
from workcell.record.batch import frames_from_columns

Columns = dict[str, NDArray[Any]]
IDS = ("session_id", "trial_id", "frame_index")


def session_info(record: SessionRecord) -> SessionInfo:
    return SessionInfo(
        mode=record.mode,
        operator_id=record.operator_id,
        seed=record.seed,
        parameters=record.parameters,
        thresholds=record.thresholds,
        metric_definitions=record.metric_definitions,
        metrics_version=record.metrics_version,
    )


def columns(store: Store, trial_id: str) -> Columns:
    """Every frame column of a trial except the ids the store fills in, with a steady wall
    clock: ``t_wall`` = first ``t_wall`` + ``t_sim``, as if recorded in real time. (A
    headless run on a busy machine stalls now and then; the sampling tests inject their
    gaps themselves.)"""
    out = {k: v for k, v in store.frames(trial_id).items() if k not in IDS}
    out["t_wall"] = out["t_wall"][0] + out["t_sim"]
    return out


def with_oscillation(
    frames: Mapping[str, NDArray[Any]],
    joint: str,
    *,
    frequency_hz: float,
    amplitude_rad: float,
    start_s: float,
    duration_s: float,
    phase: float = 0.0,
) -> Columns:
    """A sine of ``amplitude_rad`` at ``frequency_hz`` added to joint ``q_<joint>`` over
    ``start_s`` <= t_sim < ``start_s + duration_s``."""
    out = {k: np.array(v, copy=True) for k, v in frames.items()}
    t = out["t_sim"]
    window = (t >= start_s) & (t < start_s + duration_s)
    wave = amplitude_rad * np.sin(2 * np.pi * frequency_hz * (t[window] - start_s) + phase)
    out[f"q_{joint}"][window] += wave
    return out


def with_gap(frames: Mapping[str, NDArray[Any]], at_frame: int, seconds: float) -> Columns:
    """Both clocks jump by ``seconds`` before frame ``at_frame`` (frames were lost)."""
    out = {k: np.array(v, copy=True) for k, v in frames.items()}
    for clock in ("t_sim", "t_wall"):
        out[clock][at_frame:] += seconds
    return out


def with_pause(
    frames: Mapping[str, NDArray[Any]], at_frame: int, seconds: float, rate_hz: float = 20.0
) -> Columns:
    """The robot holds still for ``seconds`` before frame ``at_frame``: frame ``at_frame - 1``
    repeated at ``rate_hz`` with every rate zero, both clocks of the later frames shifted."""
    count = round(seconds * rate_hz)
    out = {}
    for name, column in frames.items():
        held = np.repeat(np.asarray(column)[at_frame - 1 : at_frame], count, axis=0)
        if name.startswith(("dq_", "base_v")):
            held = np.zeros_like(held)
        elif name in ("t_sim", "t_wall"):
            held = held + np.arange(1, count + 1) / rate_hz
        tail = np.array(column[at_frame:], copy=True)
        if name in ("t_sim", "t_wall"):
            tail += count / rate_hz
        out[name] = np.concatenate([np.array(column[:at_frame]), held, tail])
    return out


def truncated(frames: Mapping[str, NDArray[Any]], n: int) -> Columns:
    return {k: np.array(v[:n], copy=True) for k, v in frames.items()}


def frame_arrays(frames: Mapping[str, NDArray[Any]]) -> FrameArrays:
    return FrameArrays.from_columns(frames)


def thresholds(record: SessionRecord) -> MetricThresholds:
    return MetricThresholds(**record.thresholds)


def write_trial(
    store: Store,
    session_id: str,
    frames: Mapping[str, NDArray[Any]],
    outcome: str,
    *,
    interruption_reason: str | None = None,
    metric_thresholds: MetricThresholds | None = None,
    task: str | None = None,
    take_overs: Sequence[float] = (),
) -> str:
    """A closed trial of ``frames`` with the recorder's metrics; returns its id. ``task``:
    the trial's recorded ``task.kind``; ``take_overs``: the trial times a person took over
    (``take_over`` events, each handed back 1 s later)."""
    start = TrialStart(mode="collection", required_boxes=1, time_limit_s=120.0, task=task)
    trial_id = store.start_trial(session_id, start)
    store.add_frames(trial_id, frames_from_columns(frames, session_id, trial_id))
    for t in take_overs:
        store.add_event(session_id, "take_over", {}, trial_id=trial_id, t_sim=t)
        store.add_event(session_id, "hand_back", {}, trial_id=trial_id, t_sim=t + 1.0)
    t_end = float(frames["t_sim"][-1])
    success = outcome == "success"
    metrics = compute_trial_metrics(
        frame_arrays(frames), success, metric_thresholds or MetricThresholds()
    )
    store.end_trial(
        trial_id,
        TrialEnd(
            outcome=outcome,
            interruption_reason=interruption_reason,
            elapsed_s=t_end,
            completion_time_s=t_end if success else None,
            boxes_delivered=int(success),
            score=100 if success else 0,
            metrics=StoredMetrics.of(metrics),
            included=outcome != "interrupted",
            exclusion_reason="interrupted" if outcome == "interrupted" else None,
        ),
    )
    return trial_id


def replace_q(frames: FrameArrays, q: NDArray[np.float64]) -> FrameArrays:
    """``frames`` with its (n, 14) arm joint positions replaced (left then right arm)."""
    return dataclasses.replace(frames, q_l=q[:, :7], q_r=q[:, 7:])

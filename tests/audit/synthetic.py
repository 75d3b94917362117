"""Small synthetic trials written through the Store API: fast, deterministic, every column.

A trial's arms follow a smooth reach with an active grip, the base drives, the clocks tick
at 20 Hz; metrics are computed as the recorder computes them.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from tests.audit.builders import write_trial
from workcell.metrics import METRIC_DEFINITIONS, METRICS_VERSION, MetricThresholds
from workcell.record import SessionInfo, Store
from workcell.record.columns import FRAME_COLUMNS, FRAME_DEVICE_COLUMNS

RATE_HZ = 20.0
T_WALL_0 = 1_760_000_000.0


def session_info(operator_id: str = "synthetic", mode: str = "collection") -> SessionInfo:
    return SessionInfo(
        mode=mode,
        operator_id=operator_id,
        seed=0,
        parameters={"recording": {"sampling_rate_hz": RATE_HZ}},
        thresholds={
            "grip_threshold": 0.5,
            "base_linear_threshold": 0.02,
            "base_yaw_threshold": 0.05,
            "joint_rate_threshold": 0.05,
        },
        metric_definitions=METRIC_DEFINITIONS,
        metrics_version=METRICS_VERSION,
    )


def frames(n: int, seed: int) -> dict[str, NDArray[Any]]:
    """``n`` frames of one calm synthetic trial (no flag should fire)."""
    rng = np.random.default_rng(seed)
    t = np.arange(n) / RATE_HZ
    s = t / max(t[-1], 1e-9)
    out: dict[str, NDArray[Any]] = {}
    for name in FRAME_COLUMNS:
        if name not in ("session_id", "trial_id", "frame_index", "boxes", "stage"):
            out[name] = np.zeros(n)
    out["t_sim"] = t
    out["t_wall"] = T_WALL_0 + seed * 1000.0 + t * 0.98
    reach = 0.5 - 0.5 * np.cos(np.pi * s)
    for side, sign in (("l", 1.0), ("r", -1.0)):
        out[f"tcp_{side}_x"] = 2.0 * reach + rng.normal(0, 1e-3)
        out[f"tcp_{side}_y"] = sign * 0.2 + 0.5 * np.sin(np.pi * s)
        out[f"tcp_{side}_z"] = np.full(n, 0.9)
        out[f"grip_{side}"] = np.where(s > 0.05, 1.0, 0.0)
        for j in range(1, 8):
            q = 0.2 * j * reach * sign
            out[f"q_arm_{side}_{j}"] = q
            out[f"dq_arm_{side}_{j}"] = np.gradient(q) * RATE_HZ
    out["base_vx"] = 0.3 * np.sin(np.pi * s)
    for name in FRAME_DEVICE_COLUMNS:
        out[name] = np.full(n, np.nan)
    for name in ("contact_l", "contact_r", "attached"):
        out[name] = np.full(n, -1)
    for name in ("follow_l", "follow_r"):
        out[name] = np.ones(n, dtype=np.int64)
    out["boxes"] = np.array(["[]"] * n, dtype=object)
    return out


def fill(path: Path, outcomes: list[str], n_frames: int = 40) -> list[str]:
    """A store with one session holding one trial per outcome; returns the trial ids."""
    ids = []
    with Store.open(path, writer=True) as store:
        session_id = store.create_session(session_info())
        for i, outcome in enumerate(outcomes):
            reason = "application_quit" if outcome == "interrupted" else None
            ids.append(
                write_trial(
                    store,
                    session_id,
                    frames(n_frames, seed=i),
                    outcome,
                    interruption_reason=reason,
                    metric_thresholds=MetricThresholds(),
                )
            )
        store.end_session(session_id)
    return ids

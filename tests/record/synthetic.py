"""Synthetic but deterministic records: every frame column, NULL device state in some rows.

Frame ``i`` of a seed is always the same, so a test can regenerate what a writer process
wrote and compare it with what the store holds.
"""

from __future__ import annotations

import json
import sqlite3
from collections.abc import Mapping
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from workcell.record import SessionInfo, Store, StoredMetrics, TrialEnd, TrialStart
from workcell.record.batch import RowBatch, frames_from_columns
from workcell.record.columns import (
    FILTERED_POSE_COLUMNS,
    FRAME_COLUMNS,
    FRAME_DEVICE_COLUMNS,
    FRAME_INTERVENTION_COLUMNS,
    FRAME_TASK_COLUMNS,
)
from workcell.record.schema import FRAME_INTEGER_COLUMNS, FRAMES, TRIALS

RATE_HZ = 20.0
T_WALL_0 = 1_750_000_000.0
SPEEDUP = 30.0
N_BOXES = 3
_ID_COLUMNS = ("session_id", "trial_id")
_REAL_COLUMNS = tuple(
    c for c in FRAME_COLUMNS if c not in (*_ID_COLUMNS, "boxes", "stage", *FRAME_INTEGER_COLUMNS)
)
STAGES = ("none", "touched", "grasped", "lifted", "over_zone", "delivered")


def session_info(seed: int = 7) -> SessionInfo:
    return SessionInfo(
        mode="collection",
        operator_id="expert",
        seed=seed,
        parameters={"rate_hz": RATE_HZ, "grasp": "assisted", "box_score": 100},
        thresholds={"grip": 0.5, "base_linear": 0.02, "base_yaw": 0.05, "joint_rate": 0.05},
        metric_definitions={"path_length_m": "sum of TCP-midpoint steps"},
        metrics_version="1",
    )


def trial_start(seed: int = 0, *, task: bool = False, driver: bool = True) -> TrialStart:
    """A trial's start; with ``task``, its task columns and its driver (as schema version 6
    writes them)."""
    if not task:
        return TrialStart(mode="collection", required_boxes=1, time_limit_s=120.0, trial_seed=seed)
    return TrialStart(
        mode="collection",
        required_boxes=1,
        time_limit_s=120.0,
        trial_seed=seed,
        task="box_transfer",
        world="D1",
        goal={"goal_x": 1.5 + 0.01 * seed, "goal_y": -0.25},
        driver="expert" if driver else None,
    )


def drop_appended(conn: sqlite3.Connection, since: int) -> None:
    """Drop the columns schema version ``since`` and later appended (what an older store
    did not have)."""
    for layout in (TRIALS, FRAMES):
        for group in layout.added:
            if group.version >= since:
                for name in group.names:
                    conn.execute(f'ALTER TABLE {layout.name} DROP COLUMN "{name}"')


def trial_end(n_frames: int) -> TrialEnd:
    return TrialEnd(
        outcome="success",
        elapsed_s=n_frames / RATE_HZ,
        completion_time_s=n_frames / RATE_HZ,
        boxes_delivered=1,
        score=100 + 60,
        metrics=StoredMetrics(path_length_m=1.25, active_ratio=0.5, hz_sim=RATE_HZ),
        quality_flags=("low_hz_wall",),
    )


def frames(
    start: int,
    n: int,
    seed: int = 0,
    *,
    filtered: bool = True,
    task: bool | None = None,
    driver: bool = True,
) -> dict[str, NDArray[Any]]:
    """Frames ``start .. start+n-1`` as columns (without the id columns); without the
    filtered poses (as schema version 2 wrote frames) unless ``filtered``, without the task
    columns (as version 4 and older wrote them) unless ``task`` (default: ``filtered``),
    without the intervention column (as version 5 and older) unless ``task`` and
    ``driver``."""
    index = np.arange(start, start + n)
    columns: dict[str, NDArray[Any]] = {"frame_index": index}
    values = np.stack([np.random.default_rng([seed, int(i)]).normal(size=64) for i in index])
    values = values.reshape(n, 64)
    for j, name in enumerate(_REAL_COLUMNS):
        columns[name] = values[:, j % 64] * (1.0 + j)
    columns["t_sim"] = index / RATE_HZ
    columns["t_wall"] = T_WALL_0 + index / RATE_HZ / SPEEDUP
    columns["base_x"] = np.where(index % 7 == 3, -0.0, columns["base_x"])
    no_device = index % 3 == 0
    for name in FRAME_DEVICE_COLUMNS:
        columns[name] = np.where(no_device, np.nan, columns.get(name, index % 8))
    for name in ("follow_l", "follow_r"):
        columns[name] = index % 2
    for name in ("contact_l", "contact_r", "attached"):
        columns[name] = index % 3 - 1
    columns["boxes"] = np.array(
        [
            json.dumps(
                [[b, "active", 0.1 * i, -0.2, 0.8, 1.0, 0.0, 0.0, 0.0] for b in range(N_BOXES)]
            )
            for i in index
        ],
        dtype=object,
    )
    columns["stage"] = np.array([STAGES[i % len(STAGES)] for i in index], dtype=object)
    columns["progress"] = (index % 5) / 4.0
    columns["intervention"] = ((index // 4) % 2).astype(float)
    task = filtered if task is None else task
    left_out = (
        (() if filtered else FILTERED_POSE_COLUMNS)
        + (() if task else FRAME_TASK_COLUMNS)
        + (() if task and driver else FRAME_INTERVENTION_COLUMNS)
    )
    return {
        name: columns[name] for name in FRAME_COLUMNS if name in columns and name not in left_out
    }


def frame_rows(
    start: int,
    n: int,
    seed: int = 0,
    *,
    filtered: bool = True,
    task: bool | None = None,
    driver: bool = True,
) -> list[dict[str, object]]:
    """The same frames as one mapping per frame, with NULL device state as None."""
    columns = frames(start, n, seed, filtered=filtered, task=task, driver=driver)
    rows: list[dict[str, object]] = []
    for i in range(n):
        row: dict[str, object] = {}
        for name, values in columns.items():
            value = values[i].item() if isinstance(values[i], np.generic) else values[i]
            row[name] = None if isinstance(value, float) and np.isnan(value) else value
        rows.append(row)
    return rows


def batch(
    store: Store, trial_id: str, frames: Mapping[str, NDArray[Any]] | list[dict[str, object]]
) -> RowBatch:
    """Frames (as :func:`frames` or :func:`frame_rows` make them) as the batch
    :meth:`Store.add_frames` takes for the running trial ``trial_id``."""
    session_id, next_index = store.next_frame(trial_id)
    if isinstance(frames, list):
        fixed = {"session_id": session_id, "trial_id": trial_id}
        return RowBatch.from_mappings(FRAMES, frames, fixed)
    return frames_from_columns(frames, session_id, trial_id, next_index)


def fill_store(
    path: Path, *, filtered: bool = True, task: bool | None = None, driver: bool = True
) -> dict[str, list[str]]:
    """A closed store: two sessions, trials of every kind of end, events, an annotation;
    frames without filtered poses (as schema version 2 wrote them) unless ``filtered``;
    trials and frames without task columns (as version 4 and older wrote them) unless
    ``task`` (default: ``filtered``).

    Returns the ids: ``sessions`` and ``trials`` in creation order.
    """
    ids: dict[str, list[str]] = {"sessions": [], "trials": []}
    with Store.open(path, writer=True) as store:
        for s in range(2):
            session_id = store.create_session(session_info(seed=s))
            ids["sessions"].append(session_id)
            store.add_event(session_id, "session_start", {"operator": "expert"})
            for k, n in enumerate((12, 7)):
                task = filtered if task is None else task
                start = trial_start(seed=10 * s + k, task=task, driver=driver)
                trial_id = store.start_trial(session_id, start)
                ids["trials"].append(trial_id)
                store.add_event(session_id, "trial_start", trial_id=trial_id, t_sim=0.0)
                seed = 10 * s + k
                first = frames(0, 5, seed, filtered=filtered, task=task, driver=driver)
                rest = frame_rows(5, n - 5, seed, filtered=filtered, task=task, driver=driver)
                store.add_frames(trial_id, batch(store, trial_id, first))
                store.add_frames(trial_id, batch(store, trial_id, rest))
                store.commit()
                store.add_event(
                    session_id, "delivery", {"box": 0}, trial_id=trial_id, t_sim=n / RATE_HZ
                )
                end = trial_end(n) if k == 0 else interrupted_end(n)
                if task:
                    end = replace(end, stage=STAGES[-1 - k], progress=1.0 - k)
                store.end_trial(trial_id, end)
            store.end_session(session_id)
        store.annotate(ids["trials"][0], "exclude", "operator distracted", "reviewer@lab")
    return ids


def interrupted_end(n_frames: int) -> TrialEnd:
    return TrialEnd(
        outcome="interrupted",
        interruption_reason="operator_stop",
        elapsed_s=n_frames / RATE_HZ,
        boxes_delivered=0,
        score=0,
        included=False,
        exclusion_reason="interrupted",
    )

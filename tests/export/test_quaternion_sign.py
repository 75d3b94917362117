"""TCP quaternions keep one sign from frame to frame in the record, the exports and the env."""

from __future__ import annotations

import json
import sqlite3
from pathlib import Path

import numpy as np
import pyarrow.parquet as pq  # type: ignore[import-untyped, unused-ignore]
from hypothesis import given
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from tests.export.stores import Stores
from workcell.export.features import STATE_QUATERNIONS, continuous_state
from workcell.record.quaternion_sign import continuous

QUATERNION_COLUMNS = [f"tcp_{side}_{p}" for side in "lr" for p in ("qw", "qx", "qy", "qz")]

unit_quaternions = arrays(
    np.float64, (6, 2, 4), elements=st.floats(-1, 1, allow_nan=False, width=32)
).filter(lambda q: bool(np.all(np.linalg.norm(q, axis=-1) > 0.1)))


def test_a_flip_between_frames_is_undone() -> None:
    q = np.array([[0.01, 0.0, 1.0, 0.0], [-0.02, 0.0, -1.0, 0.0], [0.03, 0.0, 1.0, 0.0]])
    fixed = continuous(q[:, None, :])[:, 0, :]
    assert np.all(np.sum(fixed[1:] * fixed[:-1], axis=1) > 0)
    assert np.array_equal(fixed[0], q[0])  # the first keeps its sign
    assert np.array_equal(np.abs(fixed), np.abs(q))  # the same rotations


def test_the_first_frame_follows_a_previous_one() -> None:
    q = np.array([[[-0.1, 0.0, -1.0, 0.0]]])
    assert continuous(q, np.array([[0.1, 0.0, 1.0, 0.0]]))[0, 0, 0] == 0.1


@given(unit_quaternions)
def test_continuous_is_idempotent_and_keeps_each_rotation(q: np.ndarray) -> None:
    once = continuous(q)
    assert np.all(np.sum(once[1:] * once[:-1], axis=-1) >= 0)
    assert np.array_equal(continuous(once), once)
    same = np.isclose(np.abs(np.sum(once * q, axis=-1)), np.sum(q * q, axis=-1))
    assert np.all(same)


def _stored_quaternions(store: Path) -> dict[str, np.ndarray]:
    with sqlite3.connect(store) as db:
        rows = db.execute(
            f"SELECT trial_id, {', '.join(QUATERNION_COLUMNS)} FROM frames "
            "ORDER BY trial_id, frame_index"
        ).fetchall()
    trials: dict[str, list[tuple[float, ...]]] = {}
    for trial_id, *values in rows:
        trials.setdefault(trial_id, []).append(tuple(values))
    return {t: np.array(v).reshape(-1, 2, 4) for t, v in trials.items()}


def test_recorded_expert_trials_are_continuous_where_the_converter_flips(
    recorded: Stores,
) -> None:
    trials = _stored_quaternions(recorded.mixed)
    flips_avoided = 0
    for q in trials.values():
        assert np.all(np.sum(q[1:] * q[:-1], axis=-1) >= 0)
        flips_avoided += int(np.sum(q[:, :, 0] < -1e-6))  # w >= 0 would have flipped these
    assert flips_avoided > 0


def test_the_export_makes_older_records_continuous(lerobot_dir: Path) -> None:
    state = np.array(pq.read_table(lerobot_dir / "data").column("observation.state").to_pylist())
    columns = np.array(STATE_QUATERNIONS)
    q = state[:, columns]
    flipped = state.copy()
    flipped[:, columns] = q * np.where(q[:, :, :1] < -1e-6, -1.0, 1.0)  # as w >= 0 would
    assert not np.array_equal(flipped, state)
    assert np.allclose(continuous_state(flipped), continuous_state(state))
    info = json.loads((lerobot_dir / "meta/info.json").read_text())
    assert info["features"]["observation.state"]["shape"] == [39]

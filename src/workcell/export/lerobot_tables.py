"""The Parquet tables of a LeRobot v3.0 dataset, built with pyarrow.

Vector features are fixed-size lists (what ``datasets.Sequence(length=n)`` reads), shape-(1,)
features plain columns. ``meta/tasks.parquet`` carries pandas metadata that makes the task
text its index, as LeRobot writes (and reads) it with pandas.
"""

from __future__ import annotations

import json
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
import pyarrow as pa  # type: ignore[import-untyped, unused-ignore]
from numpy.typing import NDArray

from workcell.export.episode_data import EpisodeArrays
from workcell.export.features import ACTION_KEY, ENVIRONMENT_KEY, STATE_KEY
from workcell.export.lerobot_layout import DONE_KEY, INTERVENTION_KEY, REWARD_KEY, SUCCESS_KEY
from workcell.export.provenance import Provenance

_PANDAS_VERSION = "2.2.3"
"""The pandas version named in the tasks table's pandas metadata (any 2.x reads it)."""


def _fixed_list(matrix: NDArray[np.float64]) -> Any:
    width = matrix.shape[1]
    flat = pa.array(np.ascontiguousarray(matrix, dtype=np.float32).reshape(-1), pa.float32())
    return pa.FixedSizeListArray.from_arrays(flat, width)


def data_table(
    arrays: EpisodeArrays, episode_index: int, first_index: int, task_index: int, fps: int
) -> Any:
    """One episode's rows of ``data/chunk-*/file-*.parquet`` (a ``pyarrow.Table``)."""
    n = arrays.length
    columns = {
        STATE_KEY: _fixed_list(arrays.state),
        ENVIRONMENT_KEY: _fixed_list(arrays.environment),
        ACTION_KEY: _fixed_list(arrays.action),
        REWARD_KEY: pa.array(arrays.reward.astype(np.float32)),
        DONE_KEY: pa.array(arrays.done, pa.bool_()),
        SUCCESS_KEY: pa.array(arrays.success, pa.bool_()),
        INTERVENTION_KEY: pa.array(arrays.intervention, pa.bool_()),
        "timestamp": pa.array(arrays.timestamps(fps), pa.float32()),
        "frame_index": pa.array(np.arange(n), pa.int64()),
        "episode_index": pa.array(np.full(n, episode_index), pa.int64()),
        "index": pa.array(np.arange(first_index, first_index + n), pa.int64()),
        "task_index": pa.array(np.full(n, task_index), pa.int64()),
    }
    return pa.table(columns)


def episodes_table(rows: Sequence[Mapping[str, Any]]) -> Any:
    """``meta/episodes/chunk-*/file-*.parquet``: one row per episode, columns as given."""
    return pa.Table.from_pylist([dict(row) for row in rows])


def tasks_table(tasks: Sequence[str]) -> Any:
    """``meta/tasks.parquet``: ``task_index`` with the task text as the pandas index."""
    table = pa.table(
        {
            "task_index": pa.array(range(len(tasks)), pa.int64()),
            "task": pa.array(list(tasks), pa.string()),
        }
    )
    pandas_metadata = {
        "index_columns": ["task"],
        "column_indexes": [
            {
                "name": None,
                "field_name": None,
                "pandas_type": "unicode",
                "numpy_type": "object",
                "metadata": {"encoding": "UTF-8"},
            }
        ],
        "columns": [
            {
                "name": "task_index",
                "field_name": "task_index",
                "pandas_type": "int64",
                "numpy_type": "int64",
                "metadata": None,
            },
            {
                "name": "task",
                "field_name": "task",
                "pandas_type": "unicode",
                "numpy_type": "object",
                "metadata": None,
            },
        ],
        "creator": {"library": "pyarrow", "version": pa.__version__},
        "pandas_version": _PANDAS_VERSION,
    }
    return table.replace_schema_metadata({b"pandas": json.dumps(pandas_metadata).encode()})


_PROVENANCE_TYPES: dict[str, Any] = {
    "episode_index": pa.int64(),
    "trial_index": pa.int64(),
    "trial_seed": pa.int64(),
    "study_step": pa.int64(),
    "round": pa.int64(),
    "level": pa.int64(),
    "required_boxes": pa.int64(),
    "time_limit_s": pa.float64(),
    "elapsed_s": pa.float64(),
    "completion_time_s": pa.float64(),
    "boxes_delivered": pa.int64(),
    "score": pa.int64(),
    "n_frames": pa.int64(),
    "quality_flags": pa.list_(pa.string()),
    "included": pa.bool_(),
    "recorded_included": pa.bool_(),
    "review_at_wall": pa.float64(),
}


def provenance_table(records: Sequence[Provenance]) -> Any:
    """``meta/workcell_provenance.parquet``: one row per episode (nulls: not recorded)."""
    names = list(Provenance.__dataclass_fields__)
    schema = pa.schema([(name, _PROVENANCE_TYPES.get(name, pa.string())) for name in names])
    return pa.Table.from_pylist([r.as_dict() for r in records], schema=schema)

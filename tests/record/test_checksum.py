"""Row checksums: canonical (what is stored hashes as what was given) and sensitive."""

from __future__ import annotations

import math

import numpy as np

from tests.record import synthetic
from workcell.record.batch import RowBatch
from workcell.record.columns import (
    FILTERED_POSE_COLUMNS,
    FRAME_INTERVENTION_COLUMNS,
    FRAME_TASK_COLUMNS,
    TRIAL_DRIVER_COLUMNS,
    TRIAL_TASK_COLUMNS,
)
from workcell.record.layout import TableLayout
from workcell.record.schema import FRAMES, TRIALS


def _one(**changes: object) -> str:
    row: dict[str, object] = {**synthetic.frame_rows(3, 1)[0], **changes}
    return RowBatch.from_mappings(FRAMES, [row], {"session_id": "s", "trial_id": "t"}).checksums()[
        0
    ]


def test_stored_forms_hash_alike() -> None:
    # SQLite keeps NaN as NULL and -0.0 as 0.0; integers given as integral floats stay ints
    assert _one(ctrl_l_x=None) == _one(ctrl_l_x=math.nan)
    assert _one(base_y=-0.0) == _one(base_y=0.0)
    assert _one(contact_l=1.0) == _one(contact_l=1) == _one(contact_l=np.int64(1))
    assert _one(buttons_l=None) == _one(buttons_l=math.nan)


def test_every_value_matters() -> None:
    base = _one()
    assert _one(base_y=0.125) != _one(base_y=np.nextafter(0.125, 1.0))
    assert _one(buttons_l=0) != _one(buttons_l=None)
    assert _one(boxes="[]") != _one(boxes="[ ]")
    assert len({base, _one(tcp_r_qz=0.5), _one(attached=2), _one(gripper_l=math.inf)}) == 4


def test_every_input_form_gives_the_same_checksums() -> None:
    fixed = {"session_id": "s", "trial_id": "t"}
    columns = RowBatch.from_columns(FRAMES, synthetic.frames(0, 7), fixed).checksums()
    rows = RowBatch.from_mappings(FRAMES, synthetic.frame_rows(0, 7), fixed).checksums()
    assert columns == rows and len(set(columns)) == 7


def test_tables_do_not_share_checksums() -> None:
    batch = RowBatch.from_grouped(TRIALS, [])
    assert batch.checksums() == []


def test_appended_columns_count_only_where_a_row_holds_them() -> None:
    # frame 4 of seed 0 has device state (frames 0, 3, 6 ... have none)
    fixed = {"session_id": "s", "trial_id": "t"}
    row = synthetic.frame_rows(4, 1, task=False)[0]
    without = {k: v for k, v in row.items() if k not in FILTERED_POSE_COLUMNS}
    v2_form = RowBatch.from_mappings(VERSION_2_FRAMES, [without], fixed).checksums()[0]
    absent = RowBatch.from_mappings(FRAMES, [without], fixed).checksums()[0]
    nulls = {name: None for name in FILTERED_POSE_COLUMNS}
    held_as_null = RowBatch.from_mappings(FRAMES, [{**without, **nulls}], fixed).checksums()[0]
    assert absent == held_as_null == v2_form  # a row written before version 3 keeps its sum
    held = RowBatch.from_mappings(FRAMES, [row], fixed).checksums()[0]
    one_changed = _one(headset_filtered_qz=0.25)
    only_one = _one(**{**nulls, "ctrl_r_filtered_y": 0.0})
    assert len({held, one_changed, only_one, v2_form}) == 4


def test_the_task_columns_count_only_where_a_row_holds_them() -> None:
    fixed = {"session_id": "s", "trial_id": "t"}
    row = synthetic.frame_rows(4, 1)[0]  # every column, the task's stage and progress too
    newer = FRAME_TASK_COLUMNS + FRAME_INTERVENTION_COLUMNS
    old = {k: v for k, v in row.items() if k not in newer}
    version_4 = RowBatch.from_mappings(VERSION_4_FRAMES, [old], fixed).checksums()[0]
    absent = RowBatch.from_mappings(FRAMES, [old], fixed).checksums()[0]
    nulls = {"stage": None, "progress": None}
    assert (
        absent
        == version_4
        == RowBatch.from_mappings(FRAMES, [{**old, **nulls}], fixed).checksums()[0]
    )
    sums = {
        RowBatch.from_mappings(FRAMES, [{**old, **task}], fixed).checksums()[0]
        for task in (
            {"stage": "lifted", "progress": 0.0},
            {"stage": "lifted", "progress": None},
            {"stage": None, "progress": 0.0},
            {"stage": "grasped", "progress": 0.0},
            {"stage": "lifted", "progress": 0.5},
        )
    }
    assert len(sums | {version_4}) == 6
    # the versions' columns never pass for one another: no filtered poses, a stage held
    no_poses = {**old, **dict.fromkeys(FILTERED_POSE_COLUMNS), "stage": "lifted"}
    assert RowBatch.from_mappings(FRAMES, [no_poses], fixed).checksums()[0] not in sums


def test_the_trials_task_columns_count_only_where_a_row_holds_them() -> None:
    row: dict[str, object] = dict.fromkeys(TRIALS.names)
    row |= {"session_id": "s", "trial_id": "t", "trial_index": 0, "mode": "collection"}
    row |= {"required_boxes": 1, "time_limit_s": 60.0, "started_wall": 1.0}
    version_4 = TableLayout(
        "trials",
        tuple(c for c in TRIALS.columns if c.name not in TRIAL_TASK_COLUMNS + TRIAL_DRIVER_COLUMNS),
        TRIALS.key,
    )
    old = {k: v for k, v in row.items() if k not in TRIAL_TASK_COLUMNS + TRIAL_DRIVER_COLUMNS}
    before = RowBatch.from_mappings(version_4, [old]).checksums()[0]
    assert RowBatch.from_mappings(TRIALS, [row]).checksums()[0] == before
    held = RowBatch.from_mappings(TRIALS, [{**row, "task": "box_transfer"}]).checksums()[0]
    world = RowBatch.from_mappings(TRIALS, [{**row, "world": "box_transfer"}]).checksums()[0]
    assert len({before, held, world}) == 3


VERSION_2_FRAMES = TableLayout(
    "frames",
    tuple(c for c in FRAMES.columns if c.name not in FRAMES.appended),
    FRAMES.key,
)
"""The frames table as schema version 2 had it."""
VERSION_4_FRAMES = TableLayout(
    "frames",
    tuple(
        c for c in FRAMES.columns if c.name not in FRAME_TASK_COLUMNS + FRAME_INTERVENTION_COLUMNS
    ),
    FRAMES.key,
    added=FRAMES.added[:1],
)
"""The frames table as schema version 4 had it."""
VERSION_5_FRAMES = TableLayout(
    "frames",
    tuple(c for c in FRAMES.columns if c.name not in FRAME_INTERVENTION_COLUMNS),
    FRAMES.key,
    added=FRAMES.added[:2],
)
"""The frames table as schema version 5 had it."""


def test_the_driver_columns_count_only_where_a_row_holds_them() -> None:
    fixed = {"session_id": "s", "trial_id": "t"}
    row = synthetic.frame_rows(4, 1)[0]
    old = {k: v for k, v in row.items() if k not in FRAME_INTERVENTION_COLUMNS}
    version_5 = RowBatch.from_mappings(VERSION_5_FRAMES, [old], fixed).checksums()[0]
    absent = RowBatch.from_mappings(FRAMES, [old], fixed).checksums()[0]
    null = RowBatch.from_mappings(FRAMES, [{**old, "intervention": None}], fixed).checksums()[0]
    assert absent == version_5 == null  # a frame written before version 6 keeps its sum
    person = RowBatch.from_mappings(FRAMES, [{**old, "intervention": 1.0}], fixed).checksums()[0]
    driver = RowBatch.from_mappings(FRAMES, [{**old, "intervention": 0.0}], fixed).checksums()[0]
    assert len({version_5, person, driver}) == 3
    trial: dict[str, object] = dict.fromkeys(TRIALS.names)
    trial |= {"session_id": "s", "trial_id": "t", "trial_index": 0, "mode": "collection"}
    trial |= {"required_boxes": 1, "time_limit_s": 60.0, "started_wall": 1.0}
    sums = {
        RowBatch.from_mappings(TRIALS, [{**trial, "driver": d}]).checksums()[0]
        for d in (None, "expert", "person")
    }
    assert len(sums) == 3

"""Verification names what is wrong: the store, the table and the row."""

from __future__ import annotations

import sqlite3
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import pytest
from numpy.typing import NDArray

from tests.record import synthetic
from workcell.record import Store
from workcell.record.verify import IntegrityFinding, verify_store


@pytest.fixture
def store(tmp_path: Path) -> tuple[Path, dict[str, list[str]]]:
    path = tmp_path / "s.db"
    return path, synthetic.fill_store(path)


def _tamper(path: Path, sql: str, *params: object) -> None:
    conn = sqlite3.connect(path)
    assert conn.execute(sql, params).rowcount == 1
    conn.commit()
    conn.close()


def _where(findings: list[IntegrityFinding]) -> list[tuple[str, str, str]]:
    return [(f.store, f.table, f.row) for f in findings]


def test_a_closed_store_verifies(store: tuple[Path, dict[str, list[str]]]) -> None:
    path, _ = store
    assert verify_store(path) == []


def test_one_changed_frame_value_is_named(store: tuple[Path, dict[str, list[str]]]) -> None:
    path, ids = store
    trial = ids["trials"][2]
    _tamper(
        path,
        "UPDATE frames SET q_arm_l_3 = q_arm_l_3 + 1e-12 WHERE trial_id = ? AND frame_index = 4",
        trial,
    )
    findings = verify_store(path)
    assert _where(findings) == [
        (str(path), "frames", f"trial {trial} frame 4"),
        (str(path), "frame_blocks", f"trial {trial}"),  # q_arm_l_3 is a metric column
    ]
    assert "checksum mismatch" in findings[0].problem
    assert str(findings[0]).startswith(f"{path}: frames trial {trial} frame 4: checksum")
    assert findings[1].problem == "differs from the trial's frames"


def test_a_changed_frame_block_is_named(store: tuple[Path, dict[str, list[str]]]) -> None:
    path, ids = store
    trial = ids["trials"][1]
    with sqlite3.connect(path) as conn:
        (data,) = conn.execute(
            "SELECT data FROM frame_blocks WHERE trial_id = ?", (trial,)
        ).fetchone()
    _tamper(
        path,
        "UPDATE frame_blocks SET data = ? WHERE trial_id = ?",
        data[:80] + bytes(8) + data[88:],  # one value of the first column set to 0.0
        trial,
    )
    findings = verify_store(path)
    assert _where(findings) == [(str(path), "frame_blocks", f"trial {trial}")] * 2
    assert [f.problem for f in findings] == [
        "checksum mismatch: the block was changed after it was written",
        "differs from the trial's frames",
    ]


def test_a_forged_frame_checksum_breaks_the_trial_aggregate(
    store: tuple[Path, dict[str, list[str]]],
) -> None:
    path, ids = store
    trial = ids["trials"][0]
    # change a value and write a checksum that matches it: the row passes, the trial not
    with Store.open(path, writer=False) as reader:
        frames = reader.frames(trial)
    _tamper(
        path,
        "UPDATE frames SET grip_l = 0.75, checksum = ? WHERE trial_id = ? AND frame_index = 1",
        _forged_frame_checksum(frames, 1, grip_l=0.75),
        trial,
    )
    findings = verify_store(path)
    assert _where(findings) == [
        (str(path), "trials", f"trial {trial}"),
        (str(path), "frame_blocks", f"trial {trial}"),  # grip_l is a metric column
    ]
    assert "aggregate checksum mismatch" in findings[0].problem


def test_a_deleted_frame_is_found(store: tuple[Path, dict[str, list[str]]]) -> None:
    path, ids = store
    trial = ids["trials"][1]
    _tamper(path, "DELETE FROM frames WHERE trial_id = ? AND frame_index = 3", trial)
    problems = {(f.table, f.row, f.problem.split(":")[0]) for f in verify_store(path)}
    assert problems == {
        ("frames", f"trial {trial} frame 4", "frame_index out of sequence"),
        ("trials", f"trial {trial}", "n_frames is 7 but 6 frames are stored"),
        ("trials", f"trial {trial}", "aggregate checksum mismatch"),
        ("frame_blocks", f"trial {trial}", "differs from the trial's frames"),
    }


def test_changed_rows_of_other_tables_are_named(
    store: tuple[Path, dict[str, list[str]]],
) -> None:
    path, ids = store
    session, trial = ids["sessions"][1], ids["trials"][0]
    _tamper(path, "UPDATE trials SET score = 999 WHERE trial_id = ?", trial)
    _tamper(path, "UPDATE sessions SET operator_id = 'someone' WHERE session_id = ?", session)
    _tamper(path, "UPDATE events SET t_sim = 0.5 WHERE trial_id = ? AND kind = 'delivery'", trial)
    found = {(f.table, f.row.split()[0], f.problem.split(":")[0]) for f in verify_store(path)}
    assert found == {
        ("trials", "trial", "checksum mismatch"),  # the score
        ("sessions", "session", "checksum mismatch"),  # the operator
        ("events", "event", "checksum mismatch"),  # the event's t_sim
    }


def test_backward_time_and_bad_vocabulary_are_named(
    store: tuple[Path, dict[str, list[str]]],
) -> None:
    path, ids = store
    trial = ids["trials"][3]
    _tamper(path, "UPDATE frames SET t_sim = 0.01 WHERE trial_id = ? AND frame_index = 5", trial)
    _tamper(path, "UPDATE trials SET outcome = 'crashed' WHERE trial_id = ?", trial)
    problems = {(f.row, f.problem) for f in verify_store(path)}
    assert (f"trial {trial} frame 5", "t_sim does not increase") in problems
    assert (
        f"trial {trial}",
        "outcome 'crashed' is not one of ('success', 'timeout', 'interrupted', 'failed')",
    ) in problems


def test_a_trial_left_open_is_named_until_recovered(tmp_path: Path) -> None:
    path = tmp_path / "s.db"
    store = Store.open(path, writer=True)
    session_id = store.create_session(synthetic.session_info())
    trial_id = store.start_trial(session_id, synthetic.trial_start())
    store.add_frames(trial_id, synthetic.batch(store, trial_id, synthetic.frames(0, 5)))
    store.commit()
    assert verify_store(path) == []  # the recorder is alive
    store.close()  # as if it died: nothing closed the trial
    rows = {(f.table, f.row) for f in verify_store(path)}
    assert rows == {("trials", f"trial {trial_id}"), ("sessions", f"session {session_id}")}
    with Store.open(path, writer=True) as recovering:
        assert recovering.recovered == (trial_id,)
    assert verify_store(path) == []


def _forged_frame_checksum(
    frames: Mapping[str, NDArray[Any]], index: int, **changes: object
) -> str:
    from workcell.record.batch import RowBatch
    from workcell.record.schema import FRAMES

    row: dict[str, object] = {name: values[index] for name, values in frames.items()}
    row |= changes
    return RowBatch.from_mappings(FRAMES, [row]).checksums()[0]

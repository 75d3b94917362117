"""Schema version 5: tables, column names, ids, migrating versions 1 to 4, and refusing
what is not a readable store."""

from __future__ import annotations

import re
import sqlite3
from dataclasses import replace
from pathlib import Path

import pytest

import workcell.record.running
from tests.record import synthetic
from workcell.cli.main import main
from workcell.record import RecordError, Store, StoreError, rowio
from workcell.record.chain_tip import store_root
from workcell.record.columns import (
    FILTERED_POSE_COLUMNS,
    FRAME_COLUMNS,
    FRAME_TASK_COLUMNS,
    TRIAL_COLUMNS,
    TRIAL_TASK_COLUMNS,
)
from workcell.record.schema import APPLICATION_ID, SCHEMA_VERSION, SESSIONS
from workcell.record.verify import verify_store, verify_store_report


def _columns(conn: sqlite3.Connection, table: str) -> list[str]:
    return [row[1] for row in conn.execute(f"PRAGMA table_info({table})")]


def test_new_store_has_the_version_6_schema(tmp_path: Path) -> None:
    path = tmp_path / "s.db"
    synthetic.fill_store(path)
    conn = sqlite3.connect(path)
    assert conn.execute("PRAGMA user_version").fetchone()[0] == SCHEMA_VERSION == 6
    assert conn.execute("PRAGMA application_id").fetchone()[0] == APPLICATION_ID
    assert conn.execute("PRAGMA journal_mode").fetchone()[0] == "wal"
    meta = dict(conn.execute("SELECT key, value FROM meta"))
    assert meta["schema_version"] == "6"
    assert meta["software_version"]
    tables = {r[0] for r in conn.execute("SELECT name FROM sqlite_schema WHERE type='table'")}
    assert {"meta", "sessions", "trials", "events", "frames", "annotations", "chain"} <= tables
    # version 4: the first chain starts from the store's own root; the tip names the newest
    own = store_root(meta["store_id"])
    assert conn.execute("SELECT root, joined FROM chain_roots").fetchall() == [(own, "created")]
    first = conn.execute("SELECT previous FROM chain ORDER BY rowid LIMIT 1").fetchone()
    newest = conn.execute("SELECT head FROM chain ORDER BY rowid DESC LIMIT 1").fetchone()
    assert (first[0], meta["chain_tip_head"], meta["chain_tip_links"]) == (own, newest[0], "8")
    # the contract's names, in the contract's order, first
    assert _columns(conn, "frames")[: len(FRAME_COLUMNS) - 24] == list(FRAME_COLUMNS[:-24])
    assert _columns(conn, "trials")[: len(TRIAL_COLUMNS)] == list(TRIAL_COLUMNS)
    for table in ("sessions", "events", "annotations"):
        assert _columns(conn, table)[-1] == "checksum"
    # version 3's filtered poses, then version 5's task columns and version 6's driver
    # columns come after the checksum, as ALTER TABLE appends them
    assert _columns(conn, "frames")[-25:] == [
        "checksum",
        *FILTERED_POSE_COLUMNS,
        *FRAME_TASK_COLUMNS,
        "intervention",
    ]
    assert _columns(conn, "trials")[-7:] == ["checksum", *TRIAL_TASK_COLUMNS, "driver"]
    children = {
        table: {row[2] for row in conn.execute(f"PRAGMA foreign_key_list({table})")}
        for table in ("trials", "events", "frames", "annotations")
    }
    assert children == {
        "trials": {"sessions"},
        "events": {"sessions", "trials"},
        "frames": {"trials"},
        "annotations": {"trials"},
    }


def test_ids_are_hex_and_unique_across_stores(tmp_path: Path) -> None:
    a = synthetic.fill_store(tmp_path / "a.db")
    b = synthetic.fill_store(tmp_path / "b.db")
    ids = a["sessions"] + a["trials"] + b["sessions"] + b["trials"]
    assert len(set(ids)) == len(ids)
    assert all(re.fullmatch(r"[0-9a-f]{32}", i) for i in ids)
    with (
        Store.open(tmp_path / "a.db", writer=False) as one,
        Store.open(tmp_path / "b.db", writer=False) as two,
    ):
        assert one.meta()["store_id"] != two.meta()["store_id"]
        events = [e.event_id for e in one.events()] + [e.event_id for e in two.events()]
        assert len(set(events)) == len(events)


def test_foreign_keys_are_enforced(tmp_path: Path) -> None:
    path = tmp_path / "s.db"
    with Store.open(path, writer=True) as store, pytest.raises(RecordError, match="no trial"):
        store.annotate("0" * 32, "note", "why", "me")
    conn = sqlite3.connect(path)
    conn.execute("PRAGMA foreign_keys = ON")
    with pytest.raises(sqlite3.IntegrityError, match="FOREIGN KEY"):
        conn.execute(
            "INSERT INTO trials (session_id, trial_id, trial_index, mode, required_boxes, "
            "time_limit_s, started_wall, checksum) VALUES ('x', 'y', 0, 'm', 1, 1.0, 0.0, 'c')"
        )


def test_newer_schema_is_refused(tmp_path: Path) -> None:
    path = tmp_path / "s.db"
    synthetic.fill_store(path)
    conn = sqlite3.connect(path)
    conn.execute(f"PRAGMA user_version = {SCHEMA_VERSION + 1}")
    conn.close()
    for writer in (False, True):
        with pytest.raises(StoreError) as error:
            Store.open(path, writer=writer)
        message = str(error.value)
        assert f"schema version {SCHEMA_VERSION + 1}" in message
        assert f"reads up to {SCHEMA_VERSION}" in message
        assert "upgrade Workcell" in message and str(path) in message


def test_files_that_are_not_stores_are_refused(tmp_path: Path) -> None:
    text = tmp_path / "notes.txt"
    text.write_text("hello, not a database\n" * 100)
    other = tmp_path / "other.db"
    conn = sqlite3.connect(other)
    conn.execute("CREATE TABLE t (x)")
    conn.commit()
    conn.close()
    for path in (text, other):
        for writer in (False, True):
            with pytest.raises(StoreError, match="not a Workcell store"):
                Store.open(path, writer=writer)
    assert other.read_bytes()  # untouched
    with pytest.raises(StoreError, match="no store at"):
        Store.open(tmp_path / "missing.db", writer=False)
    with pytest.raises(StoreError, match="does not exist"):
        Store.open(tmp_path / "no" / "dir.db", writer=True)


def test_a_second_writer_is_refused_and_readers_are_not(tmp_path: Path) -> None:
    path = tmp_path / "s.db"
    with Store.open(path, writer=True) as first:
        with pytest.raises(StoreError, match="already open for writing"):
            Store.open(path, writer=True)
        session_id = first.create_session(synthetic.session_info())
        with Store.open(path, writer=False) as reader:
            assert [s.session_id for s in reader.sessions()] == [session_id]
            with pytest.raises(StoreError, match="open it as writer"):
                reader.create_session(synthetic.session_info())
        first.end_session(session_id)
    with Store.open(path, writer=True):  # released on close
        pass


def _without_tip_and_roots(conn: sqlite3.Connection) -> None:
    """What schema version 3 and older did not have: chain roots and the chain tip."""
    conn.execute("DROP TABLE chain_roots")
    conn.execute("DELETE FROM meta WHERE key LIKE 'chain_tip_%'")


def _as_version_1(path: Path) -> None:
    """Turn a store into what schema version 1 wrote: no chain table, no filtered poses,
    version 1 in the pragma, the meta table and every session row (its checksum kept
    consistent)."""
    conn = sqlite3.connect(path, isolation_level=None)
    conn.execute("BEGIN")
    conn.execute("DROP TABLE chain")
    _without_tip_and_roots(conn)
    synthetic.drop_appended(conn, 3)
    conn.execute("UPDATE meta SET value = '1' WHERE key = 'schema_version'")
    for (session_id,) in conn.execute("SELECT session_id FROM sessions").fetchall():
        rowio.update(conn, SESSIONS, {"session_id": session_id}, {"schema_version": 1})
    conn.execute("PRAGMA user_version = 1")
    conn.execute("COMMIT")
    conn.close()


def test_a_version_1_store_is_migrated_by_a_writer_and_refused_by_readers(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path = tmp_path / "old.db"
    ids = synthetic.fill_store(path, filtered=False)
    _as_version_1(path)
    with pytest.raises(StoreError) as refused:
        Store.open(path, writer=False)
    message = str(refused.value)
    assert "schema version 1" in message and "migrating it to version 6" in message
    assert f"workcell verify --recover --store {path}" in message
    with pytest.raises(StoreError, match="schema version 1"):
        verify_store(path)
    assert main(["verify", "--recover", "--store", str(path)]) == 0  # migrates it
    out = capsys.readouterr().out
    assert f"migrated: {path} from schema version 1 to 6" in out
    assert "2 sessions were chained when the store was migrated" in out
    with Store.open(path, writer=True) as store:
        meta = store.meta()
        sessions = store.sessions()
        links = store.chain()
        counts = store.counts()
    assert meta["schema_version"] == "6" and "migrated_wall" in meta
    assert [s.schema_version for s in sessions] == [1, 1]  # as they were recorded
    assert counts.trials == len(ids["trials"]) and counts.frames == 38  # every row kept
    assert len(links) == 8 and all(link.signature is None for link in links)
    assert verify_store(path) == []
    findings, stats = verify_store_report(path)
    assert findings == [] and stats.migrated_sessions == 2


def _as_version_2(path: Path) -> None:
    """Turn a store whose sessions were recorded as version 2 (see the test) into what
    schema version 2 wrote: no filtered poses in the frames, version 2 in the pragma and
    the meta table."""
    conn = sqlite3.connect(path, isolation_level=None)
    conn.execute("BEGIN")
    _without_tip_and_roots(conn)
    synthetic.drop_appended(conn, 3)
    conn.execute("UPDATE meta SET value = '2' WHERE key = 'schema_version'")
    conn.execute("PRAGMA user_version = 2")
    conn.execute("COMMIT")
    conn.close()


def test_a_version_2_store_is_migrated_with_every_checksum_and_chain_kept(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    path = tmp_path / "v2.db"
    with monkeypatch.context() as recorded_by_version_2:
        recorded_by_version_2.setattr(workcell.record.running, "SCHEMA_VERSION", 2)
        synthetic.fill_store(path, filtered=False)
    _as_version_2(path)
    conn = sqlite3.connect(path)
    before = conn.execute("SELECT trial_id, frame_index, checksum FROM frames").fetchall()
    heads = conn.execute("SELECT head FROM chain ORDER BY session_id, position").fetchall()
    conn.close()
    with pytest.raises(StoreError, match="migrating it to version 6") as refused:
        Store.open(path, writer=False)
    assert "from before the frames' filtered poses" in str(refused.value)
    assert main(["verify", "--recover", "--store", str(path)]) == 0  # migrates it
    assert f"migrated: {path} from schema version 2 to 6" in capsys.readouterr().out
    conn = sqlite3.connect(path)
    after = conn.execute("SELECT trial_id, frame_index, checksum FROM frames").fetchall()
    assert after == before and len(after) == 38
    assert conn.execute("SELECT head FROM chain ORDER BY session_id, position").fetchall() == heads
    filtered = conn.execute(f'SELECT "{FILTERED_POSE_COLUMNS[0]}" FROM frames').fetchall()
    assert filtered == [(None,)] * 38
    conn.close()
    findings, stats = verify_store_report(path)
    assert findings == []
    assert stats.migrated_sessions == 0  # the chains were not recomputed: nothing to qualify
    with Store.open(path, writer=True) as store:
        assert store.meta()["schema_version"] == "6" and "migrated_wall" not in store.meta()
        assert [s.schema_version for s in store.sessions()] == [2, 2]


def _as_version_4(path: Path) -> None:
    """Turn a store recorded without task columns (see the test) into what schema version 4
    wrote: no task columns in the trials and frames, version 4 in the pragma and meta."""
    conn = sqlite3.connect(path, isolation_level=None)
    conn.execute("BEGIN")
    synthetic.drop_appended(conn, 5)
    conn.execute("UPDATE meta SET value = '4' WHERE key = 'schema_version'")
    conn.execute("PRAGMA user_version = 4")
    conn.execute("COMMIT")
    conn.close()


def _every_row(conn: sqlite3.Connection) -> dict[str, list[tuple[object, ...]]]:
    """Every table's rows as version 4 had them (its columns, checksums included)."""
    tables = ("sessions", "trials", "events", "frames", "annotations", "chain", "chain_roots")
    out = {}
    for table in tables:
        names = [n for n in _columns(conn, table) if n not in (*TRIAL_TASK_COLUMNS, "stage")]
        names = [n for n in names if n not in (*FRAME_TASK_COLUMNS, "driver", "intervention")]
        quoted = ", ".join(f'"{n}"' for n in names)
        out[table] = conn.execute(f"SELECT {quoted} FROM {table} ORDER BY rowid").fetchall()
    return out


def test_a_version_4_store_is_migrated_with_every_row_checksum_and_link_kept(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    path = tmp_path / "v4.db"
    with monkeypatch.context() as recorded_by_version_4:
        recorded_by_version_4.setattr(workcell.record.running, "SCHEMA_VERSION", 4)
        ids = synthetic.fill_store(path, task=False)
    _as_version_4(path)
    conn = sqlite3.connect(path)
    before = _every_row(conn)
    tip = dict(conn.execute("SELECT key, value FROM meta WHERE key LIKE 'chain_tip_%'"))
    conn.close()
    with pytest.raises(StoreError, match="migrating it to version 6") as refused:
        Store.open(path, writer=False)
    assert "from before the trials' and frames' task and driver columns" in str(refused.value)
    assert main(["verify", "--recover", "--store", str(path)]) == 0  # migrates it
    assert f"migrated: {path} from schema version 4 to 6" in capsys.readouterr().out
    conn = sqlite3.connect(path)
    Store.open(tmp_path / "fresh.db", writer=True).close()
    fresh = sqlite3.connect(tmp_path / "fresh.db")
    for table in ("trials", "frames"):  # as a new store has them (merge copies rows by *)
        assert _columns(conn, table) == _columns(fresh, table), table
    fresh.close()
    assert _every_row(conn) == before  # every row, checksum and chain link as it was
    assert len(before["frames"]) == 38 and len(before["trials"]) == len(ids["trials"])
    assert dict(conn.execute("SELECT key, value FROM meta WHERE key LIKE 'chain_tip_%'")) == tip
    nulls = conn.execute("SELECT task, world, stage, progress, goal_json FROM trials").fetchall()
    assert nulls == [(None,) * 5] * 4
    assert conn.execute("SELECT count(*) FROM frames WHERE stage IS NULL").fetchone() == (38,)
    conn.close()
    findings, stats = verify_store_report(path)
    assert findings == [] and stats.migrated_sessions == 0
    # the migrated store takes trials with task columns, and verifies
    with Store.open(path, writer=True) as store:
        assert store.meta()["schema_version"] == "6"
        session_id = store.create_session(synthetic.session_info(seed=9))
        trial_id = store.start_trial(session_id, synthetic.trial_start(seed=3, task=True))
        store.add_frames(trial_id, synthetic.batch(store, trial_id, synthetic.frames(0, 6)))
        end = synthetic.trial_end(6)
        store.end_trial(trial_id, replace(end, stage="over_zone", progress=0.0))
        store.end_session(session_id)
        old, new = store.trials(ids["sessions"][0])[0], store.trials(session_id)[0]
    assert (old.task, old.world, old.stage, old.progress, old.goal) == (None,) * 5
    assert (new.task, new.world, new.stage, new.progress) == (
        "box_transfer",
        "D1",
        "over_zone",
        0.0,
    )
    assert new.goal == {"goal_x": 1.53, "goal_y": -0.25}
    assert verify_store(path) == []


def test_the_task_columns_are_covered_by_the_row_checksums(tmp_path: Path) -> None:
    path = tmp_path / "s.db"
    synthetic.fill_store(path)
    assert verify_store(path) == []
    conn = sqlite3.connect(path, isolation_level=None)
    stages = conn.execute("SELECT DISTINCT stage FROM frames").fetchall()
    assert len(stages) == len(synthetic.STAGES)
    conn.execute("UPDATE frames SET stage = 'delivered' WHERE frame_index = 2")
    conn.execute("UPDATE trials SET goal_json = '{\"goal_x\":0}' WHERE trial_index = 1")
    conn.close()
    findings = verify_store(path)
    assert {(f.table, f.problem.split(":")[0]) for f in findings if "checksum" in f.problem} >= {
        ("frames", "checksum mismatch"),
        ("trials", "checksum mismatch"),
    }, [str(f) for f in findings]


def test_a_version_5_store_is_migrated_with_every_row_kept_and_takes_drivers(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    path = tmp_path / "v5.db"
    with monkeypatch.context() as recorded_by_version_5:
        recorded_by_version_5.setattr(workcell.record.running, "SCHEMA_VERSION", 5)
        ids = synthetic.fill_store(path, task=True, driver=False)
    conn = sqlite3.connect(path, isolation_level=None)
    conn.execute("BEGIN")
    synthetic.drop_appended(conn, 6)
    conn.execute("UPDATE meta SET value = '5' WHERE key = 'schema_version'")
    conn.execute("PRAGMA user_version = 5")
    conn.execute("COMMIT")
    before = conn.execute("SELECT * FROM frames ORDER BY rowid").fetchall()
    conn.close()
    with pytest.raises(StoreError, match="migrating it to version 6") as refused:
        Store.open(path, writer=False)
    assert "from before the trials' driver and the frames' intervention" in str(refused.value)
    assert main(["verify", "--recover", "--store", str(path)]) == 0  # migrates it
    assert f"migrated: {path} from schema version 5 to 6" in capsys.readouterr().out
    conn = sqlite3.connect(path)
    assert [row[:-1] for row in conn.execute("SELECT * FROM frames ORDER BY rowid")] == before
    assert conn.execute("SELECT count(*) FROM frames WHERE intervention IS NULL").fetchone() == (
        38,
    )
    assert conn.execute("SELECT driver FROM trials").fetchall() == [(None,)] * 4
    conn.close()
    with Store.open(path, writer=True) as store:
        session_id = store.create_session(synthetic.session_info(seed=9))
        trial_id = store.start_trial(session_id, synthetic.trial_start(seed=3, task=True))
        store.add_frames(trial_id, synthetic.batch(store, trial_id, synthetic.frames(0, 8)))
        store.end_trial(trial_id, synthetic.trial_end(8))
        store.end_session(session_id)
        old, new = store.trials(ids["sessions"][0])[0], store.trials(session_id)[0]
        flags = store.frames(trial_id)["intervention"].tolist()
    assert (old.driver, new.driver) == (None, "expert")
    assert flags == [0.0] * 4 + [1.0] * 4
    assert verify_store(path) == []

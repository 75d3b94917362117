"""Schema version 4: tables, column names, ids, migrating versions 1, 2 and 3, and refusing
what is not a readable store."""

from __future__ import annotations

import re
import sqlite3
from pathlib import Path

import pytest

import workcell.record.store
from tests.record import synthetic
from workcell.cli.main import main
from workcell.record import RecordError, Store, StoreError, rowio
from workcell.record.chain_tip import store_root
from workcell.record.columns import FILTERED_POSE_COLUMNS, FRAME_COLUMNS, TRIAL_COLUMNS
from workcell.record.schema import APPLICATION_ID, FRAMES, SCHEMA_VERSION, SESSIONS
from workcell.record.verify import verify_store, verify_store_report


def _columns(conn: sqlite3.Connection, table: str) -> list[str]:
    return [row[1] for row in conn.execute(f"PRAGMA table_info({table})")]


def test_new_store_has_the_version_4_schema(tmp_path: Path) -> None:
    path = tmp_path / "s.db"
    synthetic.fill_store(path)
    conn = sqlite3.connect(path)
    assert conn.execute("PRAGMA user_version").fetchone()[0] == SCHEMA_VERSION == 4
    assert conn.execute("PRAGMA application_id").fetchone()[0] == APPLICATION_ID
    assert conn.execute("PRAGMA journal_mode").fetchone()[0] == "wal"
    meta = dict(conn.execute("SELECT key, value FROM meta"))
    assert meta["schema_version"] == "4"
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
    assert _columns(conn, "frames")[: len(FRAME_COLUMNS) - 21] == list(FRAME_COLUMNS[:-21])
    assert _columns(conn, "trials")[: len(TRIAL_COLUMNS)] == list(TRIAL_COLUMNS)
    for table in ("sessions", "trials", "events", "annotations"):
        assert _columns(conn, table)[-1] == "checksum"
    # version 3's filtered poses come after the checksum, as ALTER TABLE appends them
    assert _columns(conn, "frames")[-22:] == ["checksum", *FILTERED_POSE_COLUMNS]
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
    for name in FRAMES.appended:
        conn.execute(f'ALTER TABLE frames DROP COLUMN "{name}"')
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
    assert "schema version 1" in message and "migrating it to version 4" in message
    assert f"workcell verify --recover --store {path}" in message
    with pytest.raises(StoreError, match="schema version 1"):
        verify_store(path)
    assert main(["verify", "--recover", "--store", str(path)]) == 0  # migrates it
    out = capsys.readouterr().out
    assert f"migrated: {path} from schema version 1 to 4" in out
    assert "2 sessions were chained when the store was migrated" in out
    with Store.open(path, writer=True) as store:
        meta = store.meta()
        sessions = store.sessions()
        links = store.chain()
        counts = store.counts()
    assert meta["schema_version"] == "4" and "migrated_wall" in meta
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
    for name in FRAMES.appended:
        conn.execute(f'ALTER TABLE frames DROP COLUMN "{name}"')
    conn.execute("UPDATE meta SET value = '2' WHERE key = 'schema_version'")
    conn.execute("PRAGMA user_version = 2")
    conn.execute("COMMIT")
    conn.close()


def test_a_version_2_store_is_migrated_with_every_checksum_and_chain_kept(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    path = tmp_path / "v2.db"
    with monkeypatch.context() as recorded_by_version_2:
        recorded_by_version_2.setattr(workcell.record.store, "SCHEMA_VERSION", 2)
        synthetic.fill_store(path, filtered=False)
    _as_version_2(path)
    conn = sqlite3.connect(path)
    before = conn.execute("SELECT trial_id, frame_index, checksum FROM frames").fetchall()
    heads = conn.execute("SELECT head FROM chain ORDER BY session_id, position").fetchall()
    conn.close()
    with pytest.raises(StoreError, match="migrating it to version 4") as refused:
        Store.open(path, writer=False)
    assert "from before the frames' filtered poses" in str(refused.value)
    assert main(["verify", "--recover", "--store", str(path)]) == 0  # migrates it
    assert f"migrated: {path} from schema version 2 to 4" in capsys.readouterr().out
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
        assert store.meta()["schema_version"] == "4" and "migrated_wall" not in store.meta()
        assert [s.schema_version for s in store.sessions()] == [2, 2]

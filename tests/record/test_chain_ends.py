"""The ends of a store's chains: a session cut short and handed to a writer with the key
is not re-signed, a session grafted in from another store or grown from a copy of this
one is found, a keyed crash is recovered signed and says what it found, and stores of
schema version 3 migrate with their chains (a signed one only with its key)."""

from __future__ import annotations

import shutil
import sqlite3
from pathlib import Path

import pytest

from tests.record import synthetic
from tests.record.forgery import editing, rechain, recompute_checksums
from tests.record.test_chain import KEY, chain_problems, signed_store
from workcell.cli.main import main
from workcell.record import Store, StoreError, chain_tip
from workcell.record.merge import MergeError, merge_stores
from workcell.record.verify import verify_store


def cut_newest_session(path: Path) -> str:
    """Issue 37's attack: the newest session set back to running (its row as at its
    start), its last trial deleted with that trial's link, its events and the end link."""
    with editing(path) as conn:
        (session,) = conn.execute(
            "SELECT session_id FROM sessions ORDER BY created_wall DESC LIMIT 1"
        ).fetchone()
        (trial,) = conn.execute(
            "SELECT trial_id FROM trials WHERE session_id = ? ORDER BY trial_index DESC",
            (session,),
        ).fetchone()
        for table in ("frames", "frame_blocks"):
            conn.execute(f"DELETE FROM {table} WHERE trial_id = ?", (trial,))
        conn.execute(
            "DELETE FROM chain WHERE session_id = ? AND (subject_id = ? OR kind = 'end')",
            (session, trial),
        )
        (through,) = conn.execute(
            "SELECT max(events_through) FROM chain WHERE session_id = ?", (session,)
        ).fetchone()
        conn.execute("DELETE FROM events WHERE session_id = ? AND seq > ?", (session, through))
        conn.execute("DELETE FROM trials WHERE trial_id = ?", (trial,))
        conn.execute(
            "UPDATE sessions SET status = 'running', ended_wall = NULL, "
            "content_checksum = NULL WHERE session_id = ?",
            (session,),
        )
        recompute_checksums(conn)
    return str(session)


def test_a_session_cut_short_is_not_re_signed_by_a_writer_with_the_key(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path = tmp_path / "s.db"
    signed_store(path)
    key_file = tmp_path / "k.key"
    key_file.write_bytes(KEY.secret)
    cut_newest_session(path)
    before = path.read_bytes()

    # the tip still names the end link that was deleted: nothing writes after it
    recover = ["verify", "--recover", "--store", str(path), "--key", str(key_file)]
    assert main(recover) == 2
    (line,) = capsys.readouterr().err.splitlines()
    assert "its newest links were deleted" in line and "nothing was written" in line
    with pytest.raises(StoreError, match="its newest links were deleted"):
        Store.open(path, writer=True, key=KEY)  # what the next collect --key opens
    assert path.read_bytes() == before
    assert main(["verify", "--store", str(path), "--key", str(key_file)]) == 1
    assert "chain tip: the store's chain tip is head" in capsys.readouterr().out

    # the tip rewritten to fit, unsigned: the signed newest link shows it was rewritten
    with editing(path) as conn:
        chain_tip.write_tip(conn, None)
    with pytest.raises(StoreError, match="tip is not signed but its newest link is"):
        Store.open(path, writer=True, key=KEY)

    # and the newest link's signature taken off too: recovery closes it, unsigned, and says so
    with editing(path) as conn:
        conn.execute(
            "UPDATE chain SET signature = NULL WHERE rowid = (SELECT max(rowid) FROM chain)"
        )
        chain_tip.write_tip(conn, None)
    assert main(recover) == 1
    out = capsys.readouterr().out
    assert "not signed" in out and "every one signed" not in out
    with Store.open(path, writer=False) as reader:
        (recovery,) = [e for e in reader.events() if e.kind == "recovery"]
    payload = recovery.payload
    assert payload["signed"] is False and payload["found"]["links"] == 2


def test_a_crash_of_a_keyed_recorder_is_recovered_signed_and_says_what_it_found(
    tmp_path: Path,
) -> None:
    path = tmp_path / "s.db"
    signed_store(path)
    store = Store.open(path, writer=True, key=KEY)
    session = store.create_session(synthetic.session_info(seed=5))
    trial = store.start_trial(session, synthetic.trial_start())
    store.add_frames(trial, synthetic.batch(store, trial, synthetic.frames(0, 9)))
    store.commit()
    store.close()  # as a killed recorder leaves it: trial and session open
    with Store.open(path, writer=True, key=KEY) as recovered:
        assert recovered.recovered == (trial,)
        (recovery,) = [e for e in recovered.events() if e.kind == "recovery"]
        links = [link for link in recovered.chain() if link.session_id == session]
    payload = recovery.payload
    assert payload["signed"] is True
    assert payload["found"] == {"links": 1, "head": links[0].head}
    assert [link.kind for link in links] == ["start", "trial", "end"]
    assert verify_store(path, key=KEY) == []


def copy_sessions(source: Path, target: Path) -> None:
    """Every row and link of ``source``'s sessions copied into ``target`` by SQL."""
    with editing(target) as conn:
        conn.execute("ATTACH DATABASE ? AS source", (str(source),))
        for table in ("sessions", "trials", "events", "frames", "frame_blocks", "chain"):
            names = [r[1] for r in conn.execute(f"PRAGMA source.table_info({table})")]
            columns = ", ".join(f'"{n}"' for n in names)  # an older store has fewer
            conn.execute(
                f"INSERT INTO main.{table} ({columns}) "
                f"SELECT {columns} FROM source.{table} ORDER BY rowid"
            )
        chain_tip.write_tip(conn, None)  # the tip made to fit (unsigned: no key)


def test_a_session_copied_in_from_another_store_is_found(tmp_path: Path) -> None:
    home, foreign = tmp_path / "home.db", tmp_path / "foreign.db"
    signed_store(home)
    ids = signed_store(foreign)
    copy_sessions(foreign, home)
    problems = chain_problems(verify_store(home))
    first = f"session {ids['sessions'][0]} link 0: its chain follows head"
    assert any(p.startswith(first) and "copied in from another store" in p for p in problems)
    assert any("tip: the store's chain tip is not signed" in p for p in problems)
    keyed = chain_problems(verify_store(home, key=KEY))
    assert any(p.startswith(first) for p in keyed)

    # merging is grafting on purpose: the merged store knows the shards' roots
    shards = [tmp_path / "a.db", tmp_path / "b.db"]
    for shard in shards:
        signed_store(shard)
    merged = tmp_path / "merged.db"
    with pytest.raises(MergeError, match=f"is signed with key {KEY.key_id}: give that key"):
        merge_stores(shards, merged)  # its tip could not be signed
    merge_stores(shards, merged, key=KEY)
    assert verify_store(merged, key=KEY) == []
    with sqlite3.connect(merged) as conn:
        joined = [r[0] for r in conn.execute("SELECT joined FROM chain_roots")]
    assert sorted(joined) == ["created", "merged", "merged"]


def test_a_chain_grown_from_a_copy_of_the_store_is_found(tmp_path: Path) -> None:
    home, twin = tmp_path / "home.db", tmp_path / "twin.db"
    signed_store(home)
    shutil.copy(home, twin)
    for target in (home, twin):  # one session more in each copy
        with Store.open(target, writer=True, key=KEY) as store:
            store.end_session(store.create_session(synthetic.session_info(seed=9)))
    with sqlite3.connect(twin) as conn:
        (grown,) = conn.execute(
            "SELECT session_id FROM sessions ORDER BY created_wall DESC LIMIT 1"
        ).fetchone()
    with editing(home) as conn:
        conn.execute("ATTACH DATABASE ? AS twin", (str(twin),))
        for table in ("sessions", "events", "chain"):
            conn.execute(
                f"INSERT INTO main.{table} SELECT * FROM twin.{table} WHERE session_id = ?",
                (grown,),
            )
        chain_tip.write_tip(conn, None)
    problems = chain_problems(verify_store(home))
    assert any(
        p.startswith(f"session {grown} link 0: starts from") and "two chains grow" in p
        for p in problems
    )


def as_version_3(path: Path) -> None:
    """A store as schema version 3 wrote it (see :func:`signed_store`'s ``task``): chains
    from an empty head, no roots or tip, no task columns."""
    with editing(path) as conn:
        conn.execute(
            "UPDATE chain SET previous = '' WHERE previous = ?", (chain_tip.own_root(conn),)
        )
        rechain(conn, KEY)
        conn.execute("DROP TABLE chain_roots")
        conn.execute("DELETE FROM meta WHERE key LIKE 'chain_tip_%'")
        synthetic.drop_appended(conn, 5)
        conn.execute("UPDATE meta SET value = '3' WHERE key = 'schema_version'")
        conn.execute("PRAGMA user_version = 3")


def test_a_version_3_store_migrates_with_its_empty_root_and_a_signed_one_only_with_its_key(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path = tmp_path / "v3.db"
    signed_store(path, task=False)
    as_version_3(path)
    key_file = tmp_path / "k.key"
    key_file.write_bytes(KEY.secret)
    assert main(["verify", "--recover", "--store", str(path)]) == 2
    line = capsys.readouterr().err
    assert f"its chain is signed with key {KEY.key_id}: migrate it with that key" in line
    assert main(["verify", "--recover", "--store", str(path), "--key", str(key_file)]) == 0
    assert f"migrated: {path} from schema version 3 to 6" in capsys.readouterr().out
    assert verify_store(path, key=KEY) == []
    with Store.open(path, writer=True, key=KEY) as store:  # a new session after the old
        store.end_session(store.create_session(synthetic.session_info(seed=3)))
    assert verify_store(path, key=KEY) == []

    # a session from an older store copied into one created at version 4 is found
    home = tmp_path / "home.db"
    signed_store(home)
    old = tmp_path / "old.db"
    signed_store(old, task=False)
    as_version_3(old)
    copy_sessions(old, home)
    problems = chain_problems(verify_store(home))
    assert any("its chain starts from an empty head" in p for p in problems)

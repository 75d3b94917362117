"""The hash chain against a forger who recomputes every checksum with the project's own
functions: edited, deleted and reordered rows, trials and sessions are found by the chain;
a rebuilt chain by the key; a deleted newest session by an export's manifest."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest

from tests.record import synthetic
from tests.record.forgery import editing, rechain, recompute_checksums
from workcell.record import Store, chain_tip
from workcell.record.chain import ChainKey
from workcell.record.export_csv import export_csv
from workcell.record.verify import IntegrityFinding, verify_store

KEY = ChainKey(b"k" * 32)


def signed_store(
    path: Path, key: ChainKey | None = KEY, *, task: bool = True
) -> dict[str, list[str]]:
    """synthetic.fill_store's two sessions, recorded with ``key`` (frames without task
    columns, as schema version 4 and older wrote them, unless ``task``)."""
    ids: dict[str, list[str]] = {"sessions": [], "trials": []}
    with Store.open(path, writer=True, key=key) as store:
        for s in range(2):
            session_id = store.create_session(synthetic.session_info(seed=s))
            ids["sessions"].append(session_id)
            store.add_event(session_id, "session_start", {"operator": "expert"})
            for k, n in enumerate((12, 7)):
                trial_id = store.start_trial(session_id, synthetic.trial_start(seed=k))
                ids["trials"].append(trial_id)
                store.add_event(session_id, "trial_start", trial_id=trial_id, t_sim=0.0)
                store.add_frames(
                    trial_id,
                    synthetic.batch(
                        store, trial_id, synthetic.frames(0, n, seed=10 * s + k, task=task)
                    ),
                )
                store.commit()
                store.add_event(session_id, "level_changed", {"level": k + 1})
                store.end_trial(trial_id, synthetic.trial_end(n))
            store.end_session(session_id)
    return ids


@pytest.fixture
def store(tmp_path: Path) -> tuple[Path, dict[str, list[str]]]:
    path = tmp_path / "s.db"
    return path, signed_store(path)


def chain_problems(findings: list[IntegrityFinding]) -> list[str]:
    return [f"{f.row}: {f.problem}" for f in findings if f.table == "chain"]


def test_an_untouched_store_verifies_with_and_without_its_key(
    store: tuple[Path, dict[str, list[str]]],
) -> None:
    path, _ = store
    assert verify_store(path) == []
    assert verify_store(path, key=KEY) == []
    wrong = verify_store(path, key=ChainKey(b"w" * 32))
    assert wrong and all("not with the key given" in f.problem for f in wrong)


def test_an_edited_frame_with_every_checksum_recomputed_is_found(
    store: tuple[Path, dict[str, list[str]]],
) -> None:
    path, ids = store
    trial = ids["trials"][1]
    with editing(path) as conn:
        conn.execute(
            "UPDATE frames SET base_x = base_x + 0.5 WHERE trial_id = ? AND frame_index = 3",
            (trial,),
        )
        recompute_checksums(conn)
    findings = verify_store(path)
    assert {f.table for f in findings} == {"chain"}  # every checksum agrees; the chain not
    assert f"trial {trial} is not what its link committed to" in findings[0].problem
    assert "the closed session is not what its end link committed to" in findings[1].problem


@pytest.mark.parametrize(
    "edit",
    [
        "UPDATE frames SET stage = 'delivered' WHERE trial_id = ? AND frame_index = 3",
        "UPDATE frames SET progress = 1.0 WHERE trial_id = ? AND frame_index = 3",
        "UPDATE trials SET stage = 'delivered' WHERE trial_id = ?",
        "UPDATE trials SET goal_json = '{}' WHERE trial_id = ?",
    ],
)
def test_an_edited_task_column_with_every_checksum_recomputed_is_found(
    store: tuple[Path, dict[str, list[str]]], edit: str
) -> None:
    """The task columns (schema version 5) are chained as every other column is."""
    path, ids = store
    trial = ids["trials"][1]
    with editing(path) as conn:
        assert conn.execute(edit, (trial,)).rowcount == 1
        recompute_checksums(conn)
    findings = verify_store(path)
    assert {f.table for f in findings} == {"chain"}
    assert f"trial {trial} is not what its link committed to" in findings[0].problem


def test_a_rebuilt_chain_is_found_by_the_key_and_by_a_manifest(
    store: tuple[Path, dict[str, list[str]]], tmp_path: Path
) -> None:
    path, ids = store
    manifest = export_csv(path, tmp_path / "export")  # kept apart from the store
    with editing(path) as conn:
        conn.execute("UPDATE trials SET score = 999 WHERE trial_id = ?", (ids["trials"][2],))
        recompute_checksums(conn)
        rechain(conn)  # everything recomputed, without the key
    assert verify_store(path) == []  # what an unkeyed chain cannot show (README)
    keyed = chain_problems(verify_store(path, key=KEY))
    assert keyed and all("not signed" in p for p in keyed)
    pinned = verify_store(path, manifest=manifest)
    (changed,) = [f for f in pinned if f.table == "manifest"]
    assert changed.row == f"session {ids['sessions'][1]}"
    assert "changed since it was exported" in changed.problem
    # a forger who forges signatures without the key gets them wrong
    with editing(path) as conn:
        conn.execute("UPDATE chain SET key_id = ?, signature = head", (KEY.key_id,))
    *forged, tip = chain_problems(verify_store(path, key=KEY))
    assert forged and all("the chain was recomputed without the key" in p for p in forged)
    assert tip.startswith("tip: the store's chain tip is not signed but its newest link is")


def test_a_deleted_trial_is_found(store: tuple[Path, dict[str, list[str]]]) -> None:
    path, ids = store
    trial = ids["trials"][0]
    with editing(path) as conn:
        for table in ("frames", "events", "frame_blocks", "trials"):
            conn.execute(f"DELETE FROM {table} WHERE trial_id = ?", (trial,))
        conn.execute("UPDATE trials SET trial_index = 0 WHERE trial_id = ?", (ids["trials"][1],))
        recompute_checksums(conn)
    problems = chain_problems(verify_store(path))
    assert any(f"linked trials not in the store (deleted): ['{trial}']" in p for p in problems)


def test_reordered_trials_and_links_are_found(
    store: tuple[Path, dict[str, list[str]]], tmp_path: Path
) -> None:
    path, ids = store
    copy = tmp_path / "copy.db"
    shutil.copy(path, copy)
    first, second = ids["trials"][2], ids["trials"][3]
    with editing(path) as conn:  # swap two trials' places in their session
        conn.execute("UPDATE trials SET trial_index = 9 WHERE trial_id = ?", (first,))
        conn.execute("UPDATE trials SET trial_index = 0 WHERE trial_id = ?", (second,))
        conn.execute("UPDATE trials SET trial_index = 1 WHERE trial_id = ?", (first,))
        recompute_checksums(conn)
    problems = chain_problems(verify_store(path))
    assert any("not its closed trials in trial_index order" in p for p in problems)
    with editing(copy) as conn:  # swap two links
        session = ids["sessions"][1]
        conn.execute(
            "UPDATE chain SET position = 9 WHERE session_id = ? AND position = 1", (session,)
        )
        conn.execute(
            "UPDATE chain SET position = 1 WHERE session_id = ? AND position = 2", (session,)
        )
        conn.execute(
            "UPDATE chain SET position = 2 WHERE session_id = ? AND position = 9", (session,)
        )
    problems = chain_problems(verify_store(copy))
    assert any("links were removed, inserted or reordered" in p for p in problems)


def test_a_deleted_frame_block_or_frame_row_is_found(
    store: tuple[Path, dict[str, list[str]]], tmp_path: Path
) -> None:
    path, ids = store
    trial = ids["trials"][3]
    copy = tmp_path / "copy.db"
    shutil.copy(path, copy)
    with editing(path) as conn:
        conn.execute("DELETE FROM frames WHERE trial_id = ? AND frame_index = 6", (trial,))
        conn.execute(
            "UPDATE frames SET frame_index = frame_index - 1 WHERE trial_id = ? "
            "AND frame_index > 6",
            (trial,),
        )
        conn.execute("UPDATE trials SET n_frames = n_frames - 1 WHERE trial_id = ?", (trial,))
        recompute_checksums(conn)
    assert any(f"trial {trial} is not what" in p for p in chain_problems(verify_store(path)))
    with editing(copy) as conn:
        conn.execute("DELETE FROM frame_blocks WHERE trial_id = ?", (trial,))
    assert any(f"trial {trial} is not what" in p for p in chain_problems(verify_store(copy)))


def test_deleted_sessions_are_found_by_the_next_session_the_tip_the_key_or_a_manifest(
    store: tuple[Path, dict[str, list[str]]], tmp_path: Path
) -> None:
    path, ids = store
    manifest = export_csv(path, tmp_path / "export")
    copy = tmp_path / "copy.db"
    shutil.copy(path, copy)

    def delete_session(target: Path, session: str) -> None:
        with editing(target) as conn:
            for table in ("frames", "events", "frame_blocks", "annotations", "trials"):
                conn.execute(
                    f"DELETE FROM {table} WHERE trial_id IN "
                    "(SELECT trial_id FROM trials WHERE session_id = ?)"
                    if table not in ("events", "trials")
                    else f"DELETE FROM {table} WHERE session_id = ?",
                    (session,),
                )
            conn.execute("DELETE FROM chain WHERE session_id = ?", (session,))
            conn.execute("DELETE FROM sessions WHERE session_id = ?", (session,))

    delete_session(path, ids["sessions"][0])  # the older one: the newer one's chain follows it
    problems = chain_problems(verify_store(path))
    assert any("the session recorded before it was deleted or rewritten" in p for p in problems)

    delete_session(copy, ids["sessions"][1])  # the newest: only the store's tip refers to it
    (cut,) = chain_problems(verify_store(copy))
    assert cut.startswith("tip: the store's chain tip is head") and "links were deleted" in cut
    with editing(copy) as conn:
        chain_tip.write_tip(conn, None)  # a forger rewrites the tip to fit, without the key
    (unsigned,) = chain_problems(verify_store(copy))
    assert unsigned.startswith("tip: the store's chain tip is not signed but its newest link is")
    with editing(copy) as conn:  # and takes the signature off the newest link
        conn.execute(
            "UPDATE chain SET signature = NULL WHERE rowid = (SELECT max(rowid) FROM chain)"
        )
    assert verify_store(copy) == []  # what the store alone cannot show (README)
    link, tip = chain_problems(verify_store(copy, key=KEY))
    assert "link 3: not signed" in link and "tip: the store's chain tip is not signed" in tip
    pinned = [f for f in verify_store(copy, manifest=manifest) if f.table == "manifest"]
    assert [f.row for f in pinned] == [f"session {ids['sessions'][1]}"]
    assert "deleted since the export" in pinned[0].problem


def test_an_event_added_after_the_end_is_found(store: tuple[Path, dict[str, list[str]]]) -> None:
    path, ids = store
    session = ids["sessions"][0]
    with editing(path) as conn:
        conn.execute(
            "INSERT INTO events (event_id, session_id, trial_id, seq, t_sim, t_wall, kind, "
            "payload_json, checksum) SELECT 'e' || hex(randomblob(8)), session_id, NULL, "
            "max(seq) + 1, NULL, max(t_wall) + 1, 'note', '{}', '' FROM events "
            "WHERE session_id = ?",
            (session,),
        )
        recompute_checksums(conn)
    problems = chain_problems(verify_store(path))
    assert any("events were added after the session ended" in p for p in problems)


def test_the_manifest_carries_every_chain_head(
    store: tuple[Path, dict[str, list[str]]], tmp_path: Path
) -> None:
    path, ids = store
    manifest = export_csv(path, tmp_path / "export")
    written = json.loads((tmp_path / "export" / "manifest.json").read_text())
    assert written == json.loads(json.dumps(manifest))
    with Store.open(path, writer=False) as reader:
        links = reader.chain()
    for session in ids["sessions"]:
        mine = [link for link in links if link.session_id == session]
        assert written["sessions"][session]["chain"] == {
            "head": mine[-1].head,
            "links": len(mine),  # start, two trials, end
            "closed": True,
            "key_id": KEY.key_id,
        }
        assert len(mine) == 4
    assert verify_store(path, manifest=manifest) == []

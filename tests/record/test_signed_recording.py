"""Recording with ``--key``: ``workcell collect`` signs the chain in its store writer
process, ``workcell verify --key`` checks every signature, ``--manifest`` checks a store
against an export's chain heads."""

from __future__ import annotations

import json
import re
import secrets
from pathlib import Path

import pytest

from tests.record import synthetic
from workcell.cli.main import main
from workcell.record import Store
from workcell.record.chain import ChainKey


def test_collect_signs_and_verify_checks_the_signatures(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    key = tmp_path / "workcell.key"
    key.write_text(secrets.token_hex(32) + "\n")
    key_id = ChainKey.from_file(key).key_id
    store = tmp_path / "signed.sqlite"
    collect = ["collect", "--mode", "collection", "--trials", "1", "--json"]
    assert main([*collect, "--store", str(store), "--key", str(key)]) == 0
    capsys.readouterr()
    with Store.open(store, writer=False) as reader:
        links = reader.chain()
    assert [link.kind for link in links] == ["start", "trial", "end"]
    assert {link.key_id for link in links} == {key_id}

    assert main(["verify", "--store", str(store), "--key", str(key)]) == 0
    assert f"3 links, every one signed with key {key_id})" in capsys.readouterr().out
    assert main(["verify", "--store", str(store)]) == 0
    assert f"3 signed with key {key_id}: give --key" in capsys.readouterr().out
    other = tmp_path / "other.key"
    other.write_text(secrets.token_hex(32))
    assert main(["verify", "--store", str(store), "--key", str(other)]) == 1
    lines = capsys.readouterr().out.splitlines()
    assert len(lines) == 4 and all(f"signed with key {key_id}, not with" in x for x in lines)
    assert ": chain tip: the store's chain tip is signed with key" in lines[-1]

    export = tmp_path / "export"
    assert main(["export", "--format", "csv", "--store", str(store), "--out", str(export)]) == 0
    capsys.readouterr()
    manifest = export / "manifest.json"
    assert main(["verify", "--store", str(store), "--manifest", str(manifest)]) == 0
    assert f"matches the chain heads of {manifest}" in capsys.readouterr().out


def test_bad_key_files_are_refused_in_one_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    short = tmp_path / "short.key"
    short.write_text("abc\n")
    store = tmp_path / "s.sqlite"
    for argv in (
        ["collect", "--trials", "1", "--store", str(store), "--key", str(short)],
        ["collect", "--trials", "1", "--store", str(store), "--key", str(tmp_path / "none")],
        ["collect", "--trials", "1", "--no-store", "--key", str(short)],
    ):
        assert main(argv) == 2
        (line,) = capsys.readouterr().err.splitlines()
        assert re.match(r"workcell: error: (key file .*|--key: .*)", line), line
    assert not store.exists()
    assert main(["verify", "--csv", str(tmp_path), "--key", str(short)]) == 2
    assert "--key applies to --store only" in capsys.readouterr().err


def test_a_malformed_or_empty_manifest_is_one_line_per_problem_and_never_matches(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    store = tmp_path / "s.sqlite"
    synthetic.fill_store(store)
    with Store.open(store, writer=False) as reader:
        session = reader.sessions()[0].session_id
    manifest = tmp_path / "manifest.json"
    for links in (None, "3", 0, 2.0, True):
        chain = {"head": "a" * 64, "links": links}
        manifest.write_text(json.dumps({"sessions": {session: {"chain": chain}}}))
        assert main(["verify", "--store", str(store), "--manifest", str(manifest)]) == 1
        captured = capsys.readouterr()
        (line,) = captured.out.splitlines()
        assert f"manifest session {session}: its chain entry is malformed" in line, line
        assert "links must be a whole number of at least 1" in line
    manifest.write_text(json.dumps({"sessions": {}}))
    assert main(["verify", "--store", str(store), "--manifest", str(manifest)]) == 1
    (line,) = capsys.readouterr().out.splitlines()
    assert "pins no session's chain head, so it vouches for nothing" in line

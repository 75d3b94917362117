"""One vocabulary for inclusion from the store to the pages to the exports: an interrupted
trial is stored incomplete and not included, the Sessions page's data says so with the
reason the audit gives, and every dataset export prints what it kept and what it left
out, per reason."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from tests.export.stores import Stores
from tests.server.harness import running_server
from workcell.cli.main import main
from workcell.record.store import Store

INTERRUPTED = "incomplete: interrupted (application_quit)"
REVIEWED = "excluded by reviewer tests: operator bumped the conveyor"


def test_an_interrupted_trial_is_stored_incomplete_and_not_included(recorded: Stores) -> None:
    with Store.open(recorded.mixed, writer=False) as store:
        (trial,) = [t for t in store.trials() if t.outcome == "interrupted"]
    assert (trial.included, trial.exclusion_reason) == (False, INTERRUPTED)


def test_the_sessions_page_data_says_included_as_the_exports_do(
    recorded: Stores, tmp_path: Path
) -> None:
    shutil.copy(recorded.mixed, tmp_path / "store.sqlite")
    with running_server(tmp_path) as server:
        sessions = server.get_json("/api/sessions")["sessions"]
    trials = [t for s in sessions for t in s["trials"]]
    shown = sorted((t["outcome"], t["included"], t["exclusion_reason"]) for t in trials)
    assert shown == [
        ("interrupted", False, INTERRUPTED),
        ("success", False, REVIEWED),  # the reviewer's exclusion, as the export takes it
        ("success", True, None),
        ("timeout", True, None),
    ]


@pytest.mark.parametrize("format_", ["lerobot", "hdf5", "rerun"])
def test_every_dataset_export_prints_what_it_left_out_and_why(
    recorded: Stores, tmp_path: Path, format_: str, capsys: pytest.CaptureFixture[str]
) -> None:
    argv = ["export", "--format", format_, "--store", str(recorded.mixed)]
    assert main([*argv, "--out", str(tmp_path / "default")]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[0].startswith("exported 2 episodes, ")
    assert lines[1] == (
        "  kept 2 of 4 closed trials (1 success, 1 timeout); "
        f"left out 2: 1 excluded by reviewer, 1 {INTERRUPTED}"
    )
    assert main([*argv, "--out", str(tmp_path / "all"), "--all"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert (
        lines[1]
        == "  kept 4 of 4 closed trials (2 success, 1 timeout, 1 interrupted); left out none"
    )

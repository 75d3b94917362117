"""``bench/learn_generated.py`` fixes the audit's definition before it sees a result (issue
34, item 6: "the audit's flags and thresholds are fixed before the run"): its first run
writes the definition into the work directory, and a resumed run whose audit says
otherwise stops instead of deciding the keep-versus-all comparison after the fact."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import pytest
from bench.learn_generated import Settings, fix_audit_definition, pending, run

from workcell.audit.config import AuditConfig


def test_the_first_run_fixes_the_audit_definition_and_a_resumed_one_keeps_it(
    tmp_path: Path,
) -> None:
    fix_audit_definition(tmp_path)
    fixed = json.loads((tmp_path / "audit-definition.json").read_text())
    assert fixed["audit"]["audit_version"] == AuditConfig().describe()["audit_version"]
    assert fixed["audit"]["detectors"]["slow"] == json.loads(
        json.dumps(AuditConfig().describe()["detectors"]["slow"])
    )
    fix_audit_definition(tmp_path)  # the same definition: the run goes on

    fixed["audit"]["detectors"]["slow"]["version"] = "0"  # as if a threshold had moved
    (tmp_path / "audit-definition.json").write_text(json.dumps(fixed))
    with pytest.raises(SystemExit, match="audit's definition differs"):
        fix_audit_definition(tmp_path)


def test_quick_sizes_replace_the_full_run() -> None:
    full = Settings.parse(["--work", "w"])
    quick = Settings.parse(["--work", "w", "--quick"])
    assert (full.sources, full.attempts, full.steps, full.rollouts) == (10, 1000, 10_000, 200)
    assert (quick.sources, quick.attempts, quick.steps, quick.rollouts) == (2, 6, 20, 2)
    assert (full.time_limit_s, quick.time_limit_s) == (None, 30.0)


def test_a_step_writes_its_output_to_the_log_as_it_comes_and_returns_it(tmp_path: Path) -> None:
    (tmp_path / "commands.log").write_text("earlier step\n")
    said = run(
        tmp_path, sys.executable, "-c", "import sys; print('out'); print('err', file=sys.stderr)"
    )
    assert sorted(said.split()) == ["err", "out"]  # this step's output only, stderr with it
    log = (tmp_path / "commands.log").read_text()
    assert log.startswith("earlier step\n$ ") and log.endswith(said)
    with pytest.raises(SystemExit, match=r"failed \(3\); see commands.log"):
        run(tmp_path, sys.executable, "-c", "raise SystemExit(3)")


def test_an_unfinished_step_starts_again_from_nothing_and_a_finished_one_is_kept(
    tmp_path: Path,
) -> None:
    """A killed generation leaves a store with its side files, a killed training a
    checkpoint directory with an early checkpoint: without the step's marker they are
    removed and the step runs again; with it nothing is touched."""
    store, policy = tmp_path / "generated.sqlite", tmp_path / "act-keep"
    for leftover in (store, tmp_path / "generated.sqlite-wal", tmp_path / "generated.sqlite.lock"):
        leftover.write_text("partial")
    (policy / "checkpoints" / "last").mkdir(parents=True)
    assert pending(tmp_path / "generate.txt", store)
    assert pending(tmp_path / "train-keep.minutes", policy)
    assert sorted(p.name for p in tmp_path.iterdir()) == []

    store.write_text("whole")
    (tmp_path / "generate.txt").write_text("1000 attempts, ...\n")
    assert not pending(tmp_path / "generate.txt", store)
    assert store.read_text() == "whole"

"""Which trials a dataset export takes: the store's included ones, every one (``--all``),
the ones the audit keeps (``--audited``), successes only (``--successes``)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from tests.audit.conftest import Scenario, expert_stores, scenario
from workcell.cli.main import main
from workcell.errors import ConfigError
from workcell.export.lerobot_export import export_lerobot
from workcell.export.options import ExportOptions

__all__ = ["expert_stores", "scenario"]


def _exported(scenario: Scenario, out: Path, options: ExportOptions) -> set[str]:
    """The scenario's case names of the exported episodes."""
    export_lerobot(scenario.path, out, options)
    document = json.loads((out / "meta" / "workcell_provenance.json").read_text())
    names = {trial_id: name for name, trial_id in scenario.ids.items()}
    return {names[episode["trial_id"]] for episode in document["episodes"]}


def test_the_audit_decides_with_audited(scenario: Scenario, tmp_path: Path) -> None:
    stored = _exported(scenario, tmp_path / "stored", ExportOptions())
    assert stored == {
        "clean", "oscillating", "reviewer_included", "oscillating_timeout", "timeout", "gap"
    }  # fmt: skip
    audited = _exported(scenario, tmp_path / "audited", ExportOptions(audited=True))
    # valid and unflagged, or included by a reviewer who saw the flag
    assert audited == {"clean", "reviewer_included", "timeout"}
    kept = _exported(scenario, tmp_path / "kept", ExportOptions(audited=True, successes_only=True))
    assert kept == {"clean", "reviewer_included"}
    document = json.loads((tmp_path / "kept" / "meta" / "workcell_provenance.json").read_text())
    selection = document["selection"]
    assert selection["audited"] and selection["successes_only"]
    assert selection["left_out_not_successful"] == 1


def test_successes_alone_keep_the_stores_inclusion(scenario: Scenario, tmp_path: Path) -> None:
    successes = _exported(scenario, tmp_path / "s", ExportOptions(successes_only=True))
    assert successes == {"clean", "oscillating", "reviewer_included", "gap"}


def test_all_and_audited_do_not_go_together(
    scenario: Scenario, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    with pytest.raises(ConfigError):
        ExportOptions(include_all=True, audited=True)
    argv = ["export", "--format", "lerobot", "--store", str(scenario.path)]
    assert main([*argv, "--out", str(tmp_path / "x"), "--all", "--audited"]) == 2
    assert "--all and --audited" in capsys.readouterr().err
    assert main(["export", "--format", "csv", "--store", str(scenario.path),
                 "--out", str(tmp_path / "c"), "--successes"]) == 2  # fmt: skip
    assert "--successes: applies to the lerobot, hdf5 and rerun formats" in capsys.readouterr().err

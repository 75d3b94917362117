"""The audit's corrections (issue 35): per driver and per person, take-overs per trial, the
corrected share of frames, and success of the driver alone against with corrections, the
same from a store and from its CSV export; trials a person drove are not counted."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from tests.export.corrected import HAND_BACK_S, TAKE_OVER_S, record_corrected
from workcell.audit.interventions import UNWATCHED, corrected_seconds
from workcell.cli.main import main
from workcell.record.export_csv import export_csv


def test_corrected_time_runs_from_each_take_over_to_its_hand_back_or_the_end() -> None:
    assert corrected_seconds((), 10.0) == 0.0
    assert corrected_seconds((("take_over", 2.0), ("hand_back", 3.5)), 10.0) == 1.5
    switches = (("take_over", 1.0), ("hand_back", 2.0), ("take_over", 8.0))
    assert corrected_seconds(switches, 10.0) == 3.0  # the last one to the trial's end
    assert corrected_seconds((("take_over", -0.5), ("hand_back", 1.0)), 5.0) == 1.0


@pytest.fixture(scope="module")
def corrected_store(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """Three expert trials watched by "p07" (the second taken over) and two by "p09"
    (both taken over), all timeouts of 3 s; one session driven by a person."""
    root = tmp_path_factory.mktemp("interventions")
    store = root / "s.sqlite"
    record_corrected(store, trials=3, taken={1}, person="p07")
    record_corrected(store, trials=2, person="p09")
    assert main(["collect", "--store", str(store), "--trials", "1", "--mode", "collection",
                 "--set", "task.time_limit_s=2"]) == 0  # fmt: skip
    return store


def _groups(out: Path) -> list[dict[str, object]]:
    summary = json.loads((out / "summary.json").read_text())
    interventions = summary["interventions"]
    assert interventions["definition_version"] == 1
    groups: list[dict[str, object]] = interventions["groups"]
    return groups


def test_the_audit_reports_corrections_per_driver_and_person(
    corrected_store: Path, tmp_path: Path
) -> None:
    out = tmp_path / "audit"
    assert main(["audit", "--store", str(corrected_store), "--out", str(out)]) == 0
    groups = {(g["driver"], g["person"]): g for g in _groups(out)}
    assert set(groups) == {
        ("expert", ""),
        ("expert", "p07"),
        ("expert", "p09"),
        ("expert", UNWATCHED),  # workcell collect's expert session
    }
    share = (HAND_BACK_S - TAKE_OVER_S) / 3.0
    everyone, p07, p09 = groups["expert", ""], groups["expert", "p07"], groups["expert", "p09"]
    assert (everyone["rollouts"], everyone["take_overs"]) == (6, 3)
    assert everyone["interventions_per_trial"] == pytest.approx(3 / 6)
    assert everyone["corrected_share"] == pytest.approx(3 * share * 3.0 / (5 * 3.0 + 2.0), abs=0.02)
    assert groups["expert", UNWATCHED]["take_overs"] == 0
    assert (p07["rollouts"], p07["take_overs"]) == (3, 1)
    assert p07["corrected_share"] == pytest.approx(share / 3, abs=0.02)
    assert p09["corrected_share"] == pytest.approx(share, abs=0.02)
    alone, corrected = p07["alone"], p07["corrected"]
    assert isinstance(alone, dict) and isinstance(corrected, dict)
    assert (alone["successes"], alone["n"], corrected["successes"], corrected["n"]) == (0, 2, 0, 1)
    assert corrected["low"] == 0.0 and 0 < corrected["high"] < 1  # Wilson, 0 of 1
    p09_alone = p09["alone"]
    assert isinstance(p09_alone, dict) and p09_alone["n"] == 0  # every one taken over
    report = (out / "report.html").read_text()
    assert "<h3>Corrections</h3>" in report and "p09" in report
    # the CSV export says the same
    export = tmp_path / "csv"
    export_csv(corrected_store, export)
    from_csv = tmp_path / "audit_csv"
    assert main(["audit", "--csv", str(export), "--out", str(from_csv)]) == 0
    assert _groups(from_csv) == _groups(out)

"""``workcell audit --study FILE`` on the four-participant pilot (tests/study/conftest.py):
the design read as within-subject, the study's name and each participant's progress, the
participant x condition table rebuilt by hand from trials.csv, the Wilcoxon signed-rank
tests between the conditions and between each participant's first and second condition
against every sign assignment enumerated by hand, and words, not "nan", where a test
lacks the pairs it needs."""

from __future__ import annotations

import csv
import json
import re
import statistics
from pathlib import Path
from typing import Any

import pytest

from tests.audit.test_paired import _exact_p_by_hand, _t_sums
from tests.study.conftest import Pilot
from workcell.cli.main import EXIT_USAGE, main
from workcell.study.config import load_study
from workcell.study.plan import participant_ids, participant_plan
from workcell.study.template import TEMPLATE

PARTICIPANTS = ["p01", "p02", "p03", "p04"]
CONDITIONS = ["assisted", "physical"]


def _cells_by_hand(trials_csv: Path) -> dict[tuple[str, str], dict[str, Any]]:
    """Per (participant, condition), from the audit's own trials.csv: the trials that are
    not practice, the valid ones, the valid successes and their median completion time."""
    with trials_csv.open(newline="") as file:
        rows = [r for r in csv.DictReader(file) if r["mode"] != "practice"]
    cells = {}
    for participant in PARTICIPANTS:
        for condition in CONDITIONS:
            mine = [
                r for r in rows if (r["operator_id"], r["condition"]) == (participant, condition)
            ]
            valid = [r for r in mine if r["disposition"].startswith("valid_")]
            wins = [r for r in valid if r["disposition"] == "valid_success"]
            times = [float(r["completion_time_s"]) for r in wins]
            cells[participant, condition] = {
                "trials": len(mine),
                "valid": len(valid),
                "successes": len(wins),
                "success_rate": len(wins) / len(valid) if valid else None,
                "completion_time_s": statistics.median(times) if times else None,
            }
    return cells


def _check_test(test: dict[str, Any], first: list[Any], second: list[Any]) -> None:
    """``test`` (summary.json) against the pairs of values, by hand."""
    pairs = [(a, b) for a, b in zip(first, second, strict=True) if a is not None and b is not None]
    differences = [a - b for a, b in pairs]
    assert test["n_pairs"] == len(pairs)
    assert test["n_nonzero"] == sum(d != 0 for d in differences)
    if len(pairs) < 2 or not any(differences):
        assert test["p_value"] is None and test["missing"].startswith("no test: ")
        return
    plus, minus = _t_sums(differences)
    assert (test["t_plus"], test["t_minus"]) == pytest.approx((plus, minus))
    assert test["p_value"] == pytest.approx(_exact_p_by_hand(differences), rel=1e-9)
    assert test["rank_biserial"] == pytest.approx((plus - minus) / (plus + minus))
    assert test["low"] <= test["rank_biserial"] <= test["high"]
    assert test["missing"] is None


def test_the_audit_compares_the_conditions_within_participants(
    pilot: Pilot, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "audit"
    argv = ["audit", "--store", str(pilot.store), "--study", str(pilot.study_file)]
    assert main([*argv, "--out", str(out)]) == 0
    printed = capsys.readouterr().out
    assert "nan" not in printed
    assert (
        "  design: within-subject (study pilot: every participant runs every condition, order "
        "latin_square); paired tests over participants\n"
    ) in printed
    assert (
        "  study pilot: 4 participants, 16 of 16 planned sessions done "
        "(p01 4/4, p02 4/4, p03 4/4, p04 4/4)\n"
    ) in printed
    assert "  left out of the participant x condition table: 8 practice\n" in printed
    assert "  assisted vs physical (paired, per participant):\n" in printed
    order_label = "order: first vs second condition each participant ran"
    assert f"  {order_label} (paired, per participant):\n" in printed
    assert "    completion time: median " in printed

    summary = json.loads((out / "summary.json").read_text())
    assert summary["parameters"]["study"]["name"] == "pilot"
    assert summary["study"]["sessions_done"] == summary["study"]["sessions_planned"] == 16
    comparison = summary["comparison"]
    assert (comparison["by"], comparison["design"]) == ("condition", "within")
    assert comparison["pairs"] == []  # no pooled tests on a within-subject design
    paired = comparison["paired"]
    assert (paired["participants"], paired["conditions"]) == (PARTICIPANTS, CONDITIONS)
    study = load_study(pilot.study_file)
    orders = {
        p: list(dict.fromkeys(s.condition for s in participant_plan(study, p)))
        for p in participant_ids(study)
    }
    assert paired["orders"] == orders
    assert orders["p01"] == ["assisted", "physical"] and orders["p02"] == ["physical", "assisted"]
    assert paired["left_out"] == {"practice": 8}

    by_hand = _cells_by_hand(out / "trials.csv")
    cells = {(c["participant"], c["condition"]): c for c in paired["cells"]}
    assert set(cells) == set(by_hand)
    for key, cell in cells.items():
        expected = by_hand[key]
        assert cell["trials"] == expected["trials"] == 1
        assert (cell["valid"], cell["successes"]) == (expected["valid"], expected["successes"])
        assert cell["success_rate"] == expected["success_rate"]
        assert cell["completion_time_s"] == pytest.approx(expected["completion_time_s"])

    def values(metric: str, conditions: dict[str, str]) -> list[Any]:
        return [by_hand[p, conditions[p]][metric] for p in PARTICIPANTS]

    (between,) = paired["pairs"]
    assert (between["first"], between["second"]) == ("assisted", "physical")
    order = paired["order_effect"]
    for metric in ("success_rate", "completion_time_s"):
        assisted = values(metric, dict.fromkeys(PARTICIPANTS, "assisted"))
        physical = values(metric, dict.fromkeys(PARTICIPANTS, "physical"))
        _check_test(between["metrics"][metric], assisted, physical)
        first = values(metric, {p: orders[p][0] for p in PARTICIPANTS})
        second = values(metric, {p: orders[p][1] for p in PARTICIPANTS})
        _check_test(order["metrics"][metric], first, second)
    assert between["metrics"]["completion_time_s"]["n_pairs"] == 4  # every participant succeeded

    report = (out / "report.html").read_text()
    assert "study <b>pilot</b>" in report and "<b>Study pilot</b>" in report
    assert "Participant &times; condition" in report and 'id="paired"' in report
    assert "<th>Wilcoxon signed-rank</th>" in report
    assert "<td>p02</td><td>physical → assisted</td><td>4/4</td>" in report
    text = re.sub(r"data:image/png;base64,[A-Za-z0-9+/=]+", "", report)  # the figures
    assert "nan" not in text


def test_with_one_participant_done_the_tests_say_why_there_is_none(pilot: Pilot) -> None:
    printed = pilot.first_audit
    assert "nan" not in printed
    assert (
        "  study pilot: 4 participants, 4 of 16 planned sessions done "
        "(p01 4/4, p02 0/4, p03 0/4, p04 0/4)\n"
    ) in printed
    assert "  p02: assisted no trials; physical no trials\n" in printed
    assert (
        "    completion time: median" in printed
        and "no test: it needs 2 participants with a value in both, only 1 has one" in printed
    )


def test_without_the_study_file_the_design_is_read_from_the_trials(
    pilot: Pilot, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "audit"
    assert main(["audit", "--store", str(pilot.store), "--by", "condition", "--out", str(out)]) == 0
    printed = capsys.readouterr().out
    assert (
        "  design: within-subject (4 of 4 participants ran more than one condition (give "
        "--study FILE for the study's name and progress)); paired tests over participants"
    ) in printed
    summary = json.loads((out / "summary.json").read_text())
    assert "study" not in summary and summary["parameters"]["study"] is None
    assert summary["comparison"]["design"] == "within"


def test_a_study_file_that_cannot_be_read_is_one_clear_error(
    pilot: Pilot, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    missing = tmp_path / "nothing.toml"
    argv = ["audit", "--store", str(pilot.store), "--out", str(tmp_path / "a")]
    assert main([*argv, "--study", str(missing)]) == EXIT_USAGE
    error = capsys.readouterr().err
    assert str(missing) in error and "Traceback" not in error
    assert not (tmp_path / "a").exists()


THREE_CONDITIONS = (
    TEMPLATE.replace('name = "study"', 'name = "three"')
    .replace("participants = 12", "participants = 2")
    .replace('[[steps]]\nmode = "practice"\ntrials = 1\n\n', "")
    .replace("trials = 10", "trials = 1")
    .replace(
        '[[conditions]]\nname = "physical"',
        '[[conditions]]\nname = "assisted-again"\nsettings = { "world.grasp" = "assisted" }\n\n'
        '[[conditions]]\nname = "physical"',
    )
)


def test_three_conditions_are_compared_two_by_two_and_the_order_by_position(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    study_file, store = tmp_path / "three.toml", tmp_path / "three.sqlite"
    study_file.write_text(THREE_CONDITIONS)
    study = load_study(study_file)
    assert [c.name for c in study.conditions] == ["assisted", "assisted-again", "physical"]
    for participant in participant_ids(study):
        argv = ["study", str(study_file), "--participant", participant, "--store", str(store)]
        assert main(argv) == 0
    out = tmp_path / "audit"
    audit = ["audit", "--store", str(store), "--study", str(study_file)]
    assert main([*audit, "--out", str(out)]) == 0
    printed = capsys.readouterr().out
    assert "study three: 2 participants, 6 of 6 planned sessions done (p01 3/3, p02 3/3)" in printed
    paired = json.loads((out / "summary.json").read_text())["comparison"]["paired"]
    assert [(p["first"], p["second"]) for p in paired["pairs"]] == [
        ("assisted", "assisted-again"),
        ("assisted", "physical"),
        ("assisted-again", "physical"),
    ]
    orders = {
        p: list(dict.fromkeys(s.condition for s in participant_plan(study, p)))
        for p in participant_ids(study)
    }
    assert paired["orders"] == orders and orders["p01"] != orders["p02"]
    assert len(paired["cells"]) == 6 and paired["left_out"] == {}
    cells = {(c["participant"], c["condition"]): c for c in paired["cells"]}
    time = paired["order_effect"]["metrics"]["completion_time_s"]
    first = [cells[p, orders[p][0]]["completion_time_s"] for p in ("p01", "p02")]
    second = [cells[p, orders[p][1]]["completion_time_s"] for p in ("p01", "p02")]
    _check_test(time, first, second)
    for pair in paired["pairs"]:  # two participants: each test runs (smallest p 0.5) or says why
        test = pair["metrics"]["completion_time_s"]
        assert test["n_pairs"] == 2
        assert test["missing"] is None or test["missing"].startswith("no test: ")
        assert test["missing"] is not None or test["smallest_p"] == 0.5

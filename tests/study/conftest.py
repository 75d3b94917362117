"""The study pilot the study's output and analysis tests share: four participants (the
expert at four skills), each running their plan of a practice and a collection session in
each of two conditions, in the Latin square's orders, recorded headless by ``workcell
study --participant`` into one store."""

from __future__ import annotations

import contextlib
import io
from dataclasses import dataclass
from pathlib import Path

import pytest

from workcell.cli.main import main
from workcell.record.store import Store
from workcell.study.config import load_study
from workcell.study.plan import participant_ids, participant_plan
from workcell.study.template import TEMPLATE

Expected = dict[str, tuple[str, str, int]]
"""Each session's (participant, condition, study step), by session id."""

PILOT4 = (
    TEMPLATE.replace('name = "study"', 'name = "pilot"')
    .replace("participants = 12", "participants = 4")
    .replace("trials = 10", "trials = 1")
)
"""Four participants, two conditions, a practice and a collection of one in each."""
SKILLS = {"p01": "1.0", "p02": "0.8", "p03": "0.9", "p04": "0.7"}
TRIALS = 16
"""4 participants x 2 conditions x (1 practice + 1 collection trial)."""


@dataclass(frozen=True)
class Pilot:
    study_file: Path
    store: Path
    expected: Expected
    first_audit: str
    """What ``workcell audit --study`` printed when only p01 had run their plan."""


@pytest.fixture(scope="session")
def pilot(tmp_path_factory: pytest.TempPathFactory) -> Pilot:
    folder = tmp_path_factory.mktemp("study")
    study_file, store = folder / "study.toml", folder / "study.sqlite"
    study_file.write_text(PILOT4)
    study = load_study(study_file)
    first_audit = ""
    for participant in participant_ids(study):
        argv = ["study", str(study_file), "--participant", participant, "--store", str(store)]
        assert main([*argv, "--skill", SKILLS[participant]]) == 0
        if participant == "p01":
            audit = ["audit", "--store", str(store), "--study", str(study_file)]
            first = io.StringIO()
            with contextlib.redirect_stdout(first):
                assert main([*audit, "--out", str(folder / "first-audit")]) == 0
            first_audit = first.getvalue()
    plans = {p: participant_plan(study, p) for p in participant_ids(study)}
    expected: Expected = {}
    with Store.open(store, writer=False) as reader:
        for session in reader.sessions():
            (planned,) = [
                p for p in plans[session.operator_id] if p.config.seed == session.seed
                and p.condition == session.parameters["condition"]
            ]  # fmt: skip
            expected[session.session_id] = (
                session.operator_id,
                planned.condition,
                planned.position,
            )
    assert sorted(expected.values()) == [
        ("p01", "assisted", 1),
        ("p01", "assisted", 2),
        ("p01", "physical", 3),
        ("p01", "physical", 4),
        ("p02", "assisted", 3),
        ("p02", "assisted", 4),
        ("p02", "physical", 1),
        ("p02", "physical", 2),
        ("p03", "assisted", 1),
        ("p03", "assisted", 2),
        ("p03", "physical", 3),
        ("p03", "physical", 4),
        ("p04", "assisted", 3),
        ("p04", "assisted", 4),
        ("p04", "physical", 1),
        ("p04", "physical", 2),
    ]
    return Pilot(study_file, store, expected, first_audit)


@pytest.fixture(scope="session")
def study_store(pilot: Pilot) -> tuple[Path, Expected]:
    return pilot.store, pilot.expected

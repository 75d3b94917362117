"""Studies: the counterbalanced orders, the study file's validation and template, each
participant's plan, and a pilot run recorded into a real store that resumes where it
stopped."""

from __future__ import annotations

import itertools
import tomllib
from collections import Counter
from pathlib import Path

import pytest

from workcell.cli.main import EXIT_USAGE, main
from workcell.errors import ConfigError
from workcell.record.store import Store
from workcell.recording.recorded_session import RecordedSession, RecordedSessionConfig
from workcell.study.config import StudyConfig, load_study, study_from_mapping
from workcell.study.order import balanced_latin_square, condition_order
from workcell.study.plan import participant_ids, participant_plan
from workcell.study.progress import remaining
from workcell.study.template import TEMPLATE


@pytest.mark.parametrize("n", [2, 3, 4, 5, 6])
def test_the_latin_square_is_balanced(n: int) -> None:
    rows = balanced_latin_square(n)
    assert len(rows) == (2 * n if n % 2 else n)
    assert all(sorted(row) == list(range(n)) for row in rows)
    for position in range(n):  # every condition equally often at every position
        assert set(Counter(row[position] for row in rows).values()) == {len(rows) // n}
    follows = Counter((a, b) for row in rows for a, b in itertools.pairwise(row))
    assert set(follows) == {(a, b) for a in range(n) for b in range(n) if a != b}
    assert set(follows.values()) == {len(rows) // n}  # each ordered pair equally often


def test_fixed_and_shuffled_orders() -> None:
    assert condition_order("fixed", 3, 5, seed=0) == [0, 1, 2]
    shuffled = [condition_order("shuffled", 4, p, seed=7) for p in range(1, 9)]
    assert all(sorted(order) == [0, 1, 2, 3] for order in shuffled)
    assert len({tuple(o) for o in shuffled}) > 1
    assert shuffled == [condition_order("shuffled", 4, p, seed=7) for p in range(1, 9)]
    assert condition_order("latin_square", 2, 3, seed=0) == condition_order("latin_square", 2, 1, 0)


def test_the_template_is_the_default_study(capsys: pytest.CaptureFixture[str]) -> None:
    assert study_from_mapping(tomllib.loads(TEMPLATE)) == StudyConfig()
    assert main(["study", "--defaults"]) == 0
    assert capsys.readouterr().out == TEMPLATE


BAD = """
name = "grasp modes"
participants = 0
colour = "blue"
[session]
operator_id = "someone"
[[conditions]]
name = "assisted"
settings = { "world.grasp" = "magnetic" }
[[conditions]]
name = "assisted"
[[steps]]
mode = "warmup"
"""


def test_a_bad_study_gets_one_line_per_problem_naming_where(tmp_path: Path) -> None:
    path = tmp_path / "bad.toml"
    path.write_text(BAD)
    with pytest.raises(ConfigError) as raised:
        load_study(path)
    lines = [line.removeprefix(f"{path}: ") for line in raised.value.problems]
    allowed = (
        "name, participants, order, seed, instructions, consent, invite_days, session, "
        "conditions, steps"
    )
    assert f"colour: unknown study key; allowed: {allowed}" in lines
    assert any(line.startswith("steps[1].mode = 'warmup': must be one of") for line in lines)
    assert any(line.startswith("name = 'grasp modes': must be 1 to 64 letters") for line in lines)
    assert any(line.startswith("participants = 0: must be") for line in lines)
    assert "conditions: the name 'assisted' is used more than once" in lines
    assert len(lines) == 5, lines  # the sessions are checked once the study itself is sound


def test_session_settings_are_checked_per_condition(tmp_path: Path) -> None:
    data = tomllib.loads(TEMPLATE)
    data["session"] = {"operator_id": "x", "task": {"time_limit_s": 0}}
    data["conditions"][1]["settings"] = {"world.grasp": "magnetic"}
    with pytest.raises(ConfigError) as raised:
        study_from_mapping(data)
    lines = list(raised.value.problems)
    assert "session.operator_id: set by the study for each session; remove it" in lines
    # a problem of the [session] table is reported once, as the table's
    assert [p for p in lines if "time_limit_s" in p] == [
        "session.task.time_limit_s = 0: must be > 0 and at most 3600 s"
    ]
    assert any(p.startswith("conditions[2].settings.world.grasp = 'magnetic'") for p in lines)


def test_a_condition_picks_its_task_and_an_unknown_one_is_named(tmp_path: Path) -> None:
    data = tomllib.loads(TEMPLATE)
    careful = "tests.tasks.external_task:CarefulTransfer"
    data["conditions"][0]["settings"] = {"task.kind": "box_transfer"}
    data["conditions"][1]["settings"] = {"task.kind": careful}
    study = study_from_mapping(data)
    kinds = {p.condition: p.config.task.kind for p in participant_plan(study, "p01")}
    assert kinds == {"assisted": "box_transfer", "physical": careful}
    data["conditions"][1]["settings"] = {"task.kind": "juggling"}
    with pytest.raises(ConfigError) as raised:
        study_from_mapping(data)
    (line,) = raised.value.problems
    assert line.startswith("conditions[2].settings.task.kind = 'juggling': no such task")


def test_each_participant_runs_every_condition_on_the_same_worlds() -> None:
    study = StudyConfig(participants=4, seed=10)
    assert participant_ids(study) == ["p01", "p02", "p03", "p04"]
    first, second = participant_plan(study, "p01"), participant_plan(study, "p02")
    assert [(p.condition, p.step) for p in first] == [
        ("assisted", 1),
        ("assisted", 2),
        ("physical", 1),
        ("physical", 2),
    ]
    assert [p.condition for p in second][::2] == ["physical", "assisted"]  # counterbalanced
    seeds = {(p.condition, p.step): p.config.seed for p in first}
    assert seeds[("assisted", 1)] == seeds[("physical", 1)] == 10 + 1000 + 1
    assert seeds[("assisted", 2)] != seeds[("assisted", 1)]
    assert {p.config.seed for p in second}.isdisjoint(seeds.values())
    practice, collection = first[0].config, first[1].config
    assert (practice.task.mode, collection.task.mode, collection.task.trials) == (
        "practice",
        "collection",
        10,
    )
    assert {p.config.operator_id for p in first} == {"p01"}
    assert first[2].config.world.grasp == "physical" and first[2].config.condition == "physical"
    with pytest.raises(ValueError, match="p01 to p04"):
        participant_plan(study, "p05")


PILOT = (
    TEMPLATE.replace("participants = 12", "participants = 2")
    .replace('[[steps]]\nmode = "practice"\ntrials = 1\n\n', "")
    .replace("trials = 10", "trials = 1")
)


def test_a_pilot_run_records_the_plan_and_resumes_where_it_stopped(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    study_file, store = tmp_path / "study.toml", tmp_path / "study.sqlite"
    study_file.write_text(PILOT)
    plan = participant_plan(load_study(study_file), "p01")
    assert len(plan) == 2
    stopped = RecordedSessionConfig(session=plan[0].config, store=store)
    with RecordedSession.open(stopped) as session:  # stopped at once: interrupted
        assert session.run(should_stop=lambda: "application_quit") == "application_quit"
    assert remaining(plan, store) == plan

    assert main(["study", str(study_file), "--participant", "p01", "--store", str(store)]) == 0
    out = capsys.readouterr().out
    assert out.startswith("p01: 0 of 2 sessions done\n")
    assert "session 1/2: assisted, step 1 (collection): 1/1 successes" in out
    assert "session 2/2: physical, step 1 (collection): 1/1 successes" in out
    assert remaining(plan, store) == []
    with Store.open(store, writer=False) as reader:
        sessions = reader.sessions()
    assert [(s.operator_id, s.parameters["condition"], s.status) for s in sessions] == [
        ("p01", "assisted", "interrupted"),
        ("p01", "assisted", "completed"),
        ("p01", "physical", "completed"),
    ]

    assert main(["study", str(study_file), "--participant", "p01", "--store", str(store)]) == 0
    assert capsys.readouterr().out == "p01: 2 of 2 sessions done\n"
    assert main(["study", str(study_file), "--store", str(store)]) == 0
    printed = capsys.readouterr().out.splitlines()
    assert printed[1:] == [
        "  p01: assisted -> physical  (2/2 sessions done)",
        "  p02: physical -> assisted  (0/2 sessions done)",
    ]


def test_bad_command_lines_are_one_error_each(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    study_file = tmp_path / "study.toml"
    study_file.write_text(PILOT)
    assert main(["study"]) == EXIT_USAGE
    assert "FILE: give a study file" in capsys.readouterr().err
    assert main(["study", str(study_file), "--participant", "p01"]) == EXIT_USAGE
    assert "--participant: records into a store" in capsys.readouterr().err
    store = str(tmp_path / "s.sqlite")
    assert main(["study", str(study_file), "--participant", "p7", "--store", store]) == EXIT_USAGE
    assert "the study's are p01 to p02" in capsys.readouterr().err
    assert not Path(store).exists()


def test_a_key_of_thousands_of_characters_is_named_in_one_short_line() -> None:
    data = tomllib.loads(TEMPLATE)
    data["k" * 3000] = 1
    data["conditions"][0]["j" * 3000] = 1
    data["session"] = {"i" * 3000: 1}
    with pytest.raises(ConfigError) as raised:
        study_from_mapping(data)
    lines = list(raised.value.problems)
    assert len(lines) == 3 and all(len(line) < 300 for line in lines), lines

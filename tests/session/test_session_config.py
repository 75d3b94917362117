"""Session settings: defaults, TOML files, flags, and one line per bad value."""

from __future__ import annotations

import dataclasses
import tomllib
from pathlib import Path

import pytest

from workcell.errors import ConfigError
from workcell.session.config import RecordingConfig, SessionConfig, TaskConfig
from workcell.session.load import resolve_session_config
from workcell.settings import field_doc
from workcell.settings.template import to_toml


def write(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "session.toml"
    path.write_text(text)
    return path


def problems_of(tmp_path: Path, text: str, *overrides: str) -> list[str]:
    with pytest.raises(ConfigError) as caught:
        resolve_session_config(write(tmp_path, text), overrides)
    return list(caught.value.problems)


def test_defaults_are_the_papers() -> None:
    config = SessionConfig()
    assert config.task.mode == "practice"
    assert config.task.time_limit_s == 120.0
    assert (config.task.rounds, config.task.box_score) == (5, 100)
    assert config.task.level_boxes == (1, 2, 3)
    assert config.task.level_time_limits_s == (120.0, 100.0, 90.0)
    assert config.recording == RecordingConfig(20.0, 0.5, 0.02, 0.05, 0.05)


def test_default_toml_is_complete_commented_and_round_trips() -> None:
    text = to_toml(SessionConfig())
    assert resolve_session_config(None, ()) == SessionConfig()
    data = tomllib.loads(text)
    assert set(data) == {
        "task",
        "recording",
        "world",
        "input",
        "seed",
        "operator_id",
        "condition",
        "driver",
        "consent",
        "study_step",
    }

    def every_field(config: object, path: str) -> list[str]:
        names = []
        for field in dataclasses.fields(config):  # type: ignore[arg-type]
            assert field_doc(field), f"{path}{field.name} has no documentation"
            value = getattr(config, field.name)
            if dataclasses.is_dataclass(value):
                names += every_field(value, f"{path}{field.name}.")
            else:
                names.append(f"{path}{field.name}")
        return names

    for name in every_field(SessionConfig(), ""):
        table = data
        for part in name.split("."):
            table = table[part]
    assert text.count("\n# ") + 1 >= len(every_field(SessionConfig(), ""))


def test_file_values_and_overrides_apply_in_order(tmp_path: Path) -> None:
    path = write(
        tmp_path, '[task]\nmode = "challenge"\nrounds = 2\n[world.conveyor]\nspeed = 0.3\n'
    )
    config = resolve_session_config(path, ["task.rounds=3"], {"seed": 9, "task.mode": None})
    assert config.task.mode == "challenge"
    assert config.task.rounds == 3
    assert config.world.conveyor.speed == 0.3
    assert config.seed == 9


@pytest.mark.parametrize(
    ("text", "field"),
    [
        ("[recording]\nsampling_rate_hz = 0", "recording.sampling_rate_hz"),
        ("[recording]\nsampling_rate_hz = -20.0", "recording.sampling_rate_hz"),
        ("[recording]\nsampling_rate_hz = 800", "recording.sampling_rate_hz"),
        ("[recording]\nsampling_rate_hz = 30", "recording.sampling_rate_hz"),
        ("[recording]\ngrip_threshold = 1.5", "recording.grip_threshold"),
        ("[recording]\ngrip_threshold = 0", "recording.grip_threshold"),
        ("[recording]\nbase_linear_threshold = -0.1", "recording.base_linear_threshold"),
        ("[recording]\nbase_yaw_threshold = nan", "recording.base_yaw_threshold"),
        ("[recording]\njoint_rate_threshold = 5", "recording.joint_rate_threshold"),
        ("[task]\ntime_limit_s = 0", "task.time_limit_s"),
        ("[task]\nlevel_time_limits_s = [120, -1, 90]", "task.level_time_limits_s[1]"),
        ("[task]\nlevel_boxes = [1, 2]", "task.level_time_limits_s"),
        ("[task]\nrounds = 0", "task.rounds"),
        ('[task]\nmode = "marathon"', "task.mode"),
        ("[task]\nmode = 3", "task.mode"),
        ("[task]\nroundz = 3", "task.roundz"),
        ("[world.conveyor]\nsped = 0.3", "world.conveyor.sped"),
        ("[world.conveyor]\nspeed = -0.3", "world.conveyor.speed"),
        ('[world]\ngrasp = "magnetic"', "world.grasp"),
        ("colour = 1", "colour"),
        ('seed = "seven"', "seed"),
        ('operator_id = "a b"', "operator_id"),
    ],
)
def test_each_bad_value_is_one_line_naming_the_field(tmp_path: Path, text: str, field: str) -> None:
    problems = problems_of(tmp_path, text)
    assert len(problems) == 1, problems
    assert problems[0].startswith(f"{field} = ") or problems[0].startswith(f"{field}: ")


def test_several_problems_are_reported_together(tmp_path: Path) -> None:
    problems = problems_of(
        tmp_path,
        "[task]\nrounds = 0\nmdoe = 'x'\n[recording]\ngrip_threshold = 2\n[world.box]\nmass = -1\n",
    )
    fields = sorted(p.split(" ")[0].rstrip(":") for p in problems)
    assert fields == ["recording.grip_threshold", "task.mdoe", "task.rounds", "world.box.mass"]


def test_typo_in_a_key_is_never_ignored(tmp_path: Path) -> None:
    (problem,) = problems_of(tmp_path, "[task]\ncountdwn_s = 0\n")
    assert "task.countdwn_s: unknown setting" in problem
    assert "countdown_s" in problem  # says what is allowed


def test_malformed_and_missing_files_are_one_line(tmp_path: Path) -> None:
    (problem,) = problems_of(tmp_path, "[task\nmode = 1")
    assert "is not valid TOML" in problem
    with pytest.raises(ConfigError) as caught:
        resolve_session_config(tmp_path / "absent.toml")
    assert "does not exist" in caught.value.problems[0]


def test_bad_override_syntax(tmp_path: Path) -> None:
    (problem,) = problems_of(tmp_path, "", "task.rounds")
    assert "KEY=VALUE" in problem


def test_task_config_rejects_mismatched_levels_directly() -> None:
    with pytest.raises(ConfigError, match="one limit per level"):
        TaskConfig(level_boxes=(1, 2, 3, 4))


def test_a_key_of_thousands_of_characters_is_named_in_one_short_line() -> None:
    long_key = "k" * 3000
    with pytest.raises(ConfigError) as caught:
        resolve_session_config(None, [f"{long_key}=1", f"world.{long_key}.x=1"])
    assert [len(line) < 300 for line in caught.value.problems] == [True, True]
    assert caught.value.problems[0].startswith("kkkk")
    assert caught.value.problems[1].startswith("world.kkkk")
    assert "... (3000 characters): unknown setting; allowed here: task" in caught.value.problems[0]


def test_the_driver_is_the_person_expert_or_a_policy() -> None:
    assert SessionConfig().driver == "person"
    assert SessionConfig(driver="expert").driver == "expert"
    assert SessionConfig(driver="policy:runs/act/last").driver == "policy:runs/act/last"
    for bad in ("robot", "policy:", "Expert", "policy: x"):
        with pytest.raises(ConfigError) as refused:
            SessionConfig(driver=bad)
        (line,) = str(refused.value).splitlines()
        assert line.startswith(f"driver = {bad!r}") and "person, expert or policy:PATH" in line

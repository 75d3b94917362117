"""Every setting is declared once with its unit and documentation, and the template, the
README table and the setup page's hints are what the declarations generate."""

from __future__ import annotations

import dataclasses
import re
import tomllib
from pathlib import Path

import pytest

from workcell.errors import ConfigError
from workcell.protocol.typescript import generate
from workcell.session.config import SessionConfig, TaskConfig
from workcell.session.readme import README, REGENERATE, main, updated
from workcell.session.toml_io import from_mapping
from workcell.settings.declare import setting
from workcell.settings.hints import SettingHint, setting_hints
from workcell.settings.template import to_toml
from workcell.settings.validate import allowed_text, declared_problems
from workcell.settings.walk import Declared, leaf_settings, walk
from workcell.sim.config import RobotConfig, WorldConfig
from workcell.teleop.config import TeleopConfig

SETTINGS = list(leaf_settings(SessionConfig))
DECLARED = [*SETTINGS, *leaf_settings(TeleopConfig, "teleop.")]
HINTS_TS = Path(__file__).resolve().parents[2] / "web" / "src" / "pages" / "settingHints.ts"


@pytest.mark.parametrize("declared", DECLARED, ids=[d.key for d in DECLARED])
def test_every_setting_has_a_doc_a_unit_and_allowed_values(declared: Declared) -> None:
    spec = declared.spec
    assert spec.doc.strip(), f"{declared.key} has no documentation"
    numeric = declared.choices is None and declared.hint is not str
    if numeric:
        assert spec.unit.strip(), f"{declared.key} has no unit (use '1' for a pure number)"
    else:
        assert spec.unit == "", f"{declared.key} is a choice or text: no unit"
    assert allowed_text(spec, declared.hint)


def test_the_walk_covers_every_field_and_section() -> None:
    keys = [item.key for item in walk(SessionConfig)]
    assert len(keys) == len(set(keys))
    assert {"task", "world", "world.robot", "world.randomization"} <= set(keys)
    assert len(SETTINGS) >= 50


def test_a_field_without_a_declaration_is_refused() -> None:
    @dataclasses.dataclass(frozen=True)
    class Undeclared:
        speed: float = 1.0

    with pytest.raises(TypeError, match=r"Undeclared.speed is not declared with setting\(\)"):
        list(walk(Undeclared))


def test_the_default_template_round_trips_to_the_defaults() -> None:
    text = to_toml(SessionConfig())
    assert from_mapping(SessionConfig, tomllib.loads(text)) == SessionConfig()


def test_a_changed_configuration_round_trips_through_its_template() -> None:
    config = SessionConfig(
        task=TaskConfig(
            mode="challenge", rounds=2, level_boxes=(2, 4), level_time_limits_s=(60, 45.5)
        ),
        world=WorldConfig(grasp="physical", timestep=0.00125),
        seed=2**63 - 1,
        operator_id="op.7-b_c",
    )
    assert from_mapping(SessionConfig, tomllib.loads(to_toml(config))) == config


def test_each_template_comment_says_what_the_setting_allows() -> None:
    lines = to_toml(SessionConfig()).splitlines()
    for d in SETTINGS:
        name = d.key.rsplit(".", 1)[-1]
        index = next(
            i
            for i, line in enumerate(lines)
            if line.startswith(f"{name} = ") and lines[i - 1].startswith(f"# {d.spec.doc} (")
        )
        assert lines[index - 1] == f"# {d.spec.doc} ({allowed_text(d.spec, d.hint)})"


def test_the_readme_table_matches_the_declarations() -> None:
    committed = README.read_text(encoding="utf-8")
    assert committed == updated(committed), (
        f"the settings table in {README} is stale: run `{REGENERATE}` and commit the README"
    )
    for d in SETTINGS:
        assert f"| `{d.key}` |" in committed


def test_check_mode_reports_a_stale_table(tmp_path: Path) -> None:
    readme = tmp_path / "README.md"
    stale = updated(README.read_text(encoding="utf-8")).replace(
        "| `seed` | `0` |", "| `seed` | `1` |"
    )
    readme.write_text(stale, encoding="utf-8")
    assert main(["--check", "--readme", str(readme)]) == 1
    assert main(["--readme", str(readme)]) == 0
    assert main(["--check", "--readme", str(readme)]) == 0


def test_hints_follow_the_declarations() -> None:
    hints = {h.key: h for h in setting_hints(SessionConfig).hints}
    assert list(hints) == [d.key for d in SETTINGS]
    speed = hints["world.conveyor.speed"]
    assert (speed.unit, speed.low, speed.high, speed.whole) == ("m/s", 0.01, 1.0, False)
    assert speed.allowed == "between 0.01 and 1 m/s"
    boxes = hints["task.level_boxes"]
    assert boxes.whole and (boxes.low, boxes.high) == (1, 20)
    assert hints["task.time_limit_s"].low_open


def test_the_setup_pages_hint_type_is_generated_from_the_python_one() -> None:
    body = generate().split("export interface SettingHint {")[1].split("}")[0]
    ts_fields = re.findall(r"readonly (\w+):", body)
    assert ts_fields == [f.name for f in dataclasses.fields(SettingHint)]
    page = HINTS_TS.read_text(encoding="utf-8")
    assert 'import type { SettingHint, SettingHints } from "../protocol";' in page
    assert "interface SettingHint" not in page


def test_a_declaration_change_reaches_the_validation() -> None:
    @dataclasses.dataclass(frozen=True)
    class Small:
        count: int = setting(3, "how many", unit="boxes", low=1, high=5)

    assert declared_problems(Small(), "small") == []
    assert declared_problems(Small(count=6), "small") == [
        "small.count = 6: must be a whole number from 1 to 5 boxes"
    ]


def test_a_setting_taken_over_is_declared_like_its_source() -> None:
    robot = {d.name: d for d in leaf_settings(RobotConfig)}
    teleop = {d.name: d for d in leaf_settings(TeleopConfig)}
    speed = teleop["max_linear_speed"]
    assert speed.default == robot["max_linear_speed"].default
    assert (speed.spec.unit, speed.spec.low, speed.spec.high) == ("m/s", 0.05, 2.0)
    assert "stick" in speed.spec.doc
    with pytest.raises(ConfigError, match=r"teleop.max_yaw_rate = 9: must be between 0.1 and 4"):
        TeleopConfig(max_yaw_rate=9.0)

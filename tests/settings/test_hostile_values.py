"""Every declared numeric setting given hostile values through the entry points a user has
(a TOML file, ``--set KEY=VALUE``, a mapping such as a study's session table): each ends
in a clean ConfigError whose lines name the setting, or in a valid configuration whose
every derived value can be computed; never in another exception."""

from __future__ import annotations

import datetime
import functools
import math
import tomllib
from collections.abc import Callable
from pathlib import Path
from typing import Any, get_origin

import pytest

from workcell.envs.config import BoxTransferConfig
from workcell.errors import ConfigError
from workcell.session.config import SessionConfig
from workcell.session.load import resolve_session_config
from workcell.session.toml_io import from_mapping
from workcell.settings.template import to_toml
from workcell.settings.walk import Declared, leaf_settings
from workcell.teleop.config import TeleopConfig
from workcell.teleop.rate import at_teleop_rate

NUMERIC = [
    d
    for d in leaf_settings(SessionConfig)
    if d.hint in (int, float) or (get_origin(d.hint) is tuple)
]
DIGITS_400 = "1" + "0" * 399
DIGITS_5000 = "1" + "0" * 4999
HOSTILE_TEXT = (
    "1e-310",
    "-1e-310",
    "5e-324",
    "1e308",
    "-1e308",
    "1.7976931348623157e308",
    "-0.0",
    "0",
    "nan",
    "-nan",
    "inf",
    "-inf",
    str(2**63),
    str(2**64),
    "-" + str(2**63 + 1),
    DIGITS_400,
    "-" + DIGITS_400,
    DIGITS_5000,
    "true",
    "false",
    '"1e-310"',
    '"text"',
    '""',
    "[]",
    "{}",
    "1979-05-27T07:32:00Z",
    "07:32:00",
    "[" * 450 + "]" * 450,
    "[" * 5000 + "]" * 5000,
    "{a = " * 600 + "1" + "}" * 600,
)
"""Values as TOML (a file's value or the VALUE of ``--set``)."""


def _nested_list(depth: int) -> list[Any]:
    value: list[Any] = []
    for _ in range(depth):
        value = [value]
    return value


HOSTILE_VALUES: tuple[object, ...] = (
    1e-310,
    -1e-310,
    5e-324,
    1e308,
    -1e308,
    -0.0,
    math.nan,
    math.inf,
    -math.inf,
    2**63,
    2**64,
    10**399,
    -(10**399),
    10**4999,
    True,
    False,
    "1e-310",
    "text",
    None,
    {},
    datetime.date(1979, 5, 27),
    _nested_list(900),
)
"""Values as a mapping holds them (a study's ``[session]`` table, a stored session)."""
LONGEST_LINE = 400


def _derive_everything(config: SessionConfig) -> None:
    """Every value derived from a configuration, as the simulation, the recorder, the
    teleoperation and the environment compute them."""
    for each in (config, at_teleop_rate(config)):
        assert each.physics_steps_per_frame >= 1
        assert each.world.control_substeps >= 1
        assert each.world.robot.ik_every >= 1
        assert math.isfinite(each.world.physics_hz)
    TeleopConfig.for_session(config)
    assert from_mapping(SessionConfig, tomllib.loads(to_toml(config))) == config
    try:
        environment = BoxTransferConfig(session=config)
    except ConfigError:
        return
    assert environment.fps >= 1
    assert environment.control_steps_per_frame >= 1
    assert environment.max_episode_steps >= 0
    assert environment.episode_session.task.time_limit_s == environment.limit_s


def _outcome(declared: Declared, label: str, build: Callable[[], SessionConfig]) -> str | None:
    """What went wrong building a configuration with a hostile value (None: nothing)."""
    try:
        config = build()
    except ConfigError as error:
        lines = list(error.problems)
        if not any(declared.key in line for line in lines):
            return f"{declared.key} = {label}: no line names the setting: {lines}"
        for line in lines:
            if "\n" in line or len(line) > LONGEST_LINE:
                return f"{declared.key} = {label}: not one short line: {line[:200]!r}..."
        return None
    except Exception as error:
        return f"{declared.key} = {label}: {type(error).__name__}: {str(error)[:200]}"
    try:
        _derive_everything(config)
    except Exception as error:
        return f"{declared.key} = {label} passed validation, then {type(error).__name__}: {error}"
    return None


def _nested(key: str, value: object) -> dict[str, Any]:
    data: dict[str, Any] = {}
    table = data
    *parents, leaf = key.split(".")
    for part in parents:
        table = table.setdefault(part, {})
    table[leaf] = value
    return data


def _texts(declared: Declared) -> list[str]:
    """Hostile values of a setting as TOML: alone, and as every item of a list."""
    if get_origin(declared.hint) is not tuple:
        return list(HOSTILE_TEXT)
    default = [repr(v) for v in declared.default]  # type: ignore[attr-defined]
    texts = list(HOSTILE_TEXT)
    for text in HOSTILE_TEXT:
        texts.append("[" + ", ".join([text] * len(default)) + "]")
        texts.append("[" + ", ".join([text, *default[1:]]) + "]")
    return texts


def _values(declared: Declared) -> list[object]:
    if get_origin(declared.hint) is not tuple:
        return list(HOSTILE_VALUES)
    default = list(declared.default)  # type: ignore[call-overload]
    values = list(HOSTILE_VALUES)
    for value in HOSTILE_VALUES:
        values += [[value] * len(default), [value, *default[1:]]]
    return values


@pytest.mark.parametrize("declared", NUMERIC, ids=[d.key for d in NUMERIC])
def test_a_hostile_value_is_a_clean_error_or_a_valid_configuration(
    declared: Declared, tmp_path: Path
) -> None:
    failures: list[str | None] = []
    path = tmp_path / "session.toml"
    for text in _texts(declared):
        *parents, leaf = declared.key.split(".")
        table = f"[{'.'.join(parents)}]\n" if parents else ""
        path.write_text(f"{table}{leaf} = {text}\n", encoding="utf-8")
        label = text[:40]
        from_file = functools.partial(resolve_session_config, path)
        from_set = functools.partial(resolve_session_config, None, [f"{declared.key}={text}"])
        failures += [_outcome(declared, label, from_file), _outcome(declared, label, from_set)]
    for value in _values(declared):
        mapping = _nested(declared.key, value)
        from_data = functools.partial(from_mapping, SessionConfig, mapping)
        failures.append(_outcome(declared, type(value).__name__, from_data))
    found = [f for f in failures if f is not None]
    assert not found, "\n".join(found)


def test_the_walk_covers_every_numeric_setting() -> None:
    keys = {d.key for d in NUMERIC}
    assert {"recording.sampling_rate_hz", "world.robot.ik_hz", "seed", "world.box.size"} <= keys
    assert len(NUMERIC) >= 50

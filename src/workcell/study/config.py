"""A study file: who takes part, the conditions they compare, what they do in each.

A study is TOML (``workcell study --defaults`` prints a commented one). Every participant
runs every condition, in the order ``order`` gives them (:mod:`workcell.study.order`); in
each condition they run the study's ``steps`` in turn (e.g. a practice trial, then ten
collection trials), each step one recorded session. A condition is a name and the session
settings it changes (``settings = { "world.grasp" = "physical" }``, keys as in
``workcell config``); ``session`` holds the settings every session starts from. Loading
checks everything at once: one line per problem, naming where it is
(``conditions[2].settings.world.grasp``).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from workcell.errors import ConfigError, cut, shown
from workcell.session.config import Mode, SessionConfig
from workcell.session.load import resolve_session_config
from workcell.session.toml_io import from_mapping, load_toml
from workcell.settings import declared_problems, setting
from workcell.study.order import Order

NAME_PATTERN = r"[\w.-]{1,64}"
NAME_DOC = "1 to 64 letters, digits, '.', '_' or '-'"
SET_BY_STUDY = (
    "operator_id",
    "condition",
    "consent",
    "study_step",
    "seed",
    "task.mode",
    "task.trials",
)
"""Session settings the study sets itself for each session (participant, condition,
consent, its place in the participant's plan, seed, step)."""


@dataclass(frozen=True)
class Condition:
    """One condition: its name (stored on every session as ``condition``) and the session
    settings it changes."""

    name: str = setting(
        "assisted", "the condition's name", pattern=NAME_PATTERN, pattern_doc=NAME_DOC
    )
    settings: Mapping[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        problems = declared_problems(self, "")
        if problems:
            raise ConfigError(problems)


@dataclass(frozen=True)
class Step:
    """What a participant does in each condition, one recorded session per step."""

    mode: Mode = setting("collection", "practice, collection or challenge")
    trials: int = setting(
        10,
        "collection: trials in the session (practice runs one)",
        unit="trials",
        low=1,
        high=10000,
    )

    def __post_init__(self) -> None:
        problems = declared_problems(self, "")
        if problems:
            raise ConfigError(problems)


@dataclass(frozen=True)
class StudyConfig:
    """The study: its participants, order, conditions and steps."""

    name: str = setting("study", "the study's name", pattern=NAME_PATTERN, pattern_doc=NAME_DOC)
    participants: int = setting(
        12, "how many participants the plan holds", unit="participants", low=1, high=10000
    )
    order: Order = setting(
        "latin_square",
        "order of the conditions: latin_square (balanced), fixed (as listed) or shuffled",
    )
    seed: int = setting(
        0,
        "study seed: each participant's sessions derive theirs from it",
        unit="1",
        low=0,
        high=2**40,
    )
    instructions: str = setting("", "what participants read before their first trial")
    consent: str = setting("", "the consent text participants accept before their first trial")
    invite_days: float = setting(
        0.0,
        "days each participant's invite link opens their session once issued (0: it never expires)",
        unit="days",
        low=0,
        high=3650,
    )
    session: Mapping[str, Any] = field(default_factory=dict)
    conditions: tuple[Condition, ...] = (
        Condition("assisted", {"world.grasp": "assisted"}),
        Condition("physical", {"world.grasp": "physical"}),
    )
    steps: tuple[Step, ...] = (Step("practice", 1), Step("collection", 10))

    def __post_init__(self) -> None:
        problems = declared_problems(self, "")
        names = [c.name for c in self.conditions]
        if not self.conditions:
            problems.append("conditions: a study needs at least one condition")
        for name in sorted({n for n in names if names.count(n) > 1}):
            problems.append(f"conditions: the name {name!r} is used more than once")
        if not self.steps:
            problems.append("steps: a study needs at least one step")
        if problems:
            raise ConfigError(problems)

    def condition(self, name: str) -> Condition:
        return next(c for c in self.conditions if c.name == name)


def _dotted(data: Mapping[str, Any], prefix: str = "") -> dict[str, Any]:
    """``{"world": {"grasp": "physical"}}`` as ``{"world.grasp": "physical"}``."""
    flat: dict[str, Any] = {}
    for key, value in data.items():
        if isinstance(value, Mapping):
            flat |= _dotted(value, f"{prefix}{key}.")
        else:
            flat[f"{prefix}{key}"] = value
    return flat


def condition_session(study: StudyConfig, condition: Condition) -> SessionConfig:
    """The study's session settings with ``condition``'s changes (ConfigError if bad)."""
    return resolve_session_config(flags=_dotted(study.session) | _dotted(condition.settings))


def _session_problems(settings: Mapping[str, Any]) -> list[str]:
    # Imported here: the built-in tasks bring the simulation, which a reader of a study
    # file (the audit of a CSV export, tests/record/test_no_physics.py) does not load.
    from workcell.tasks.registry import task_class  # noqa: PLC0415

    try:
        task_class(resolve_session_config(flags=settings).task.kind)
    except ConfigError as error:
        return list(error.problems)
    return []


def _check_sessions(study: StudyConfig) -> list[str]:
    """The problems of every condition's sessions. One the ``[session]`` table has in
    every condition that shows it is reported once, as the table's
    (``session.world.grsap``); the rest as the condition's."""
    problems: list[str] = []
    shared = _dotted(study.session)
    for key in shared:
        if key in SET_BY_STUDY:
            problems.append(f"session.{key}: set by the study for each session; remove it")
    of_session = _session_problems(shared)
    reported: set[str] = set()
    for i, condition in enumerate(study.conditions, start=1):
        where = f"conditions[{i}].settings."
        changes = _dotted(condition.settings)
        for key in changes:
            if key in SET_BY_STUDY:
                problems.append(f"{where}{key}: set by the study for each session; remove it")
        for line in _session_problems(shared | changes):
            if line not in of_session:
                problems.append(f"{where}{line}")
            elif line not in reported:
                reported.add(line)
                problems.append(f"session.{line}")
    return problems


def _table_list(data: Mapping[str, Any], key: str, problems: list[str]) -> list[Mapping[str, Any]]:
    items = data.get(key, [])
    if not isinstance(items, list) or not all(isinstance(i, Mapping) for i in items):
        problems.append(f"{key}: must be a list of tables ([[{key}]])")
        return []
    return items


def study_from_mapping(data: Mapping[str, Any]) -> StudyConfig:
    """A validated study from TOML data; ConfigError with one line per problem."""
    problems: list[str] = []
    allowed = (
        "name",
        "participants",
        "order",
        "seed",
        "instructions",
        "consent",
        "invite_days",
        "session",
    )
    allowed_all = (*allowed, "conditions", "steps")
    for key in data:
        if key not in allowed_all:
            problems.append(f"{cut(key)}: unknown study key; allowed: {', '.join(allowed_all)}")
    session = data.get("session", {})
    if not isinstance(session, Mapping):
        problems.append("session: must be a table of session settings")
        session = {}
    conditions, steps = [], []
    raw_conditions = _table_list(data, "conditions", problems)
    raw_steps = _table_list(data, "steps", problems)
    for i, item in enumerate(raw_conditions, start=1):
        settings = item.get("settings", {})
        if not isinstance(settings, Mapping):
            problems.append(f"conditions[{i}].settings: must be a table of session settings")
            settings = {}
        extra = set(item) - {"name", "settings"}
        if extra:
            problems.append(
                f"conditions[{i}]: unknown keys {shown(sorted(extra))}; allowed: name, settings"
            )
        try:
            conditions.append(Condition(item.get("name", ""), dict(settings)))
        except ConfigError as error:
            problems += [f"conditions[{i}].{line}" for line in error.problems]
    for i, item in enumerate(raw_steps, start=1):
        try:
            steps.append(from_mapping(Step, item))
        except ConfigError as error:
            problems += [f"steps[{i}].{line}" for line in error.problems]
    scalars = {k: data[k] for k in allowed if k in data and k != "session"}
    try:
        study = StudyConfig(
            **scalars,
            session=dict(session),
            # an item already reported does not also count as missing
            conditions=tuple(conditions)
            if len(conditions) == len(raw_conditions)
            else StudyConfig.conditions,
            steps=tuple(steps) if len(steps) == len(raw_steps) else StudyConfig.steps,
        )
    except ConfigError as error:
        problems += error.problems
        raise ConfigError(problems) from None
    problems += _check_sessions(study)
    if problems:
        raise ConfigError(problems)
    return study


def load_study(path: Path) -> StudyConfig:
    """Read and validate a study file."""
    data = load_toml(path, "study file")
    try:
        return study_from_mapping(data)
    except ConfigError as error:
        raise ConfigError([f"{path}: {line}" for line in error.problems]) from None

"""The session settings of each share of an evaluation: the settings as ``workcell
collect`` resolves them (defaults, ``--config``, ``--set``), then the world's ranges, the
collection of the share's rollouts, the evaluation's seed and the operator's id."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

from workcell.errors import ConfigError
from workcell.evaluate.plan import Share
from workcell.session.config import SessionConfig
from workcell.session.load import resolve_session_config
from workcell.tasks import world_overrides
from workcell.tasks.registry import task_class

RANDOMIZATION = "world.randomization."
SET_BY_EVALUATE = ("task.mode", "task.trials", "task.first_trial", "seed", "operator_id")
"""Settings every share sets itself (``--world``, ``--rollouts``, ``--seed``, the operator)."""


def override_problems(overrides: Sequence[str]) -> list[str]:
    """``--set`` keys that evaluate sets itself, refused rather than silently replaced."""
    problems = []
    for override in overrides:
        key = override.partition("=")[0].strip()
        if key.startswith(RANDOMIZATION):
            problems.append(
                f"--set {key}: evaluate sets every world.randomization range from --world; "
                "drop it (a world of your own: workcell collect --set ...)"
            )
        elif key in SET_BY_EVALUATE:
            problems.append(
                f"--set {key}: evaluate sets it (--world, --rollouts, --seed, --policy); drop it"
            )
    return problems


def base_config(
    config_file: Path | None, overrides: Sequence[str], task: str | None
) -> SessionConfig:
    """The settings every share starts from (raises ConfigError, naming every problem)."""
    flags: dict[str, Any] = {"task.kind": task, "task.mode": "collection"}
    config = resolve_session_config(config_file, overrides, flags)
    task_class(config.task.kind, "--task")  # an unknown task is refused before anything runs
    return config


def share_config(
    config_file: Path | None,
    overrides: Sequence[str],
    task: str | None,
    share: Share,
    *,
    seed: int,
    operator_id: str,
) -> SessionConfig:
    """The session that runs ``share``'s rollouts."""
    kind = base_config(config_file, overrides, task).task.kind
    flags: dict[str, Any] = {
        "task.kind": kind,
        "task.mode": "collection",
        "task.first_trial": share.first,
        "task.trials": share.end,
        "seed": seed,
        "operator_id": operator_id,
        **world_overrides(task_class(kind).worlds[share.world]),
    }
    try:
        return resolve_session_config(config_file, overrides, flags)
    except ConfigError as error:
        raise ConfigError([f"world {share.world}: {p}" for p in error.problems]) from None

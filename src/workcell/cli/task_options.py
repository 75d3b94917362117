"""``--task`` and ``--world``: which task a command's sessions run, and in which world.

``--task NAME`` sets ``task.kind``. ``--world D0|D1|D2`` sets every
``world.randomization.*`` range to the task's world of that name
(:mod:`workcell.tasks.worlds`), so it cannot be combined with ``--set
world.randomization.*``.
"""

from __future__ import annotations

import argparse
from collections.abc import Sequence
from typing import Any

from workcell.errors import ConfigError
from workcell.tasks.worlds import WORLDS

RANDOMIZATION = "world.randomization."


def add_task_argument(parser: argparse.ArgumentParser) -> None:
    """``--task NAME``, as every command that runs or reads a task takes it."""
    parser.add_argument(
        "--task",
        metavar="NAME",
        help="the task (default: box_transfer; 'workcell tasks' lists them), or "
        "module:Class for a task of your own",
    )


def add_task_arguments(parser: argparse.ArgumentParser) -> None:
    """``--task`` and ``--world`` (one named world)."""
    add_task_argument(parser)
    parser.add_argument(
        "--world",
        choices=WORLDS,
        help="the task's world: D0 narrow (the default world), D1 moderate, D2 broad "
        "(sets world.randomization.*)",
    )


def task_flags(args: argparse.Namespace, overrides: Sequence[str]) -> dict[str, Any]:
    """The settings ``--task`` and ``--world`` stand for (dotted keys), for
    :func:`workcell.session.load.resolve_session_config`'s flags. ``--world`` needs the
    task's class, which ``--task`` (or else the configured ``task.kind``) names."""
    flags: dict[str, Any] = {"task.kind": args.task}
    if args.world is None:
        return flags
    clash = [o.partition("=")[0] for o in overrides if o.startswith(RANDOMIZATION)]
    if clash:
        raise ConfigError(
            [
                f"--world {args.world} sets every world.randomization range; it cannot go with "
                f"--set {clash[0]} (drop one of them)"
            ]
        )
    from workcell.tasks import world_overrides  # noqa: PLC0415
    from workcell.tasks.registry import DEFAULT_TASK, task_class  # noqa: PLC0415

    task = task_class(args.task or _configured_kind(args) or DEFAULT_TASK, "--task")
    flags.update(world_overrides(task.worlds[args.world]))
    return flags


def _configured_kind(args: argparse.Namespace) -> str | None:
    """The ``task.kind`` of ``--config`` or ``--set``, if either names one."""
    from workcell.session.load import resolve_session_config  # noqa: PLC0415

    try:
        return resolve_session_config(args.config, args.set).task.kind
    except ConfigError:
        return None

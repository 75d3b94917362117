"""``workcell tasks``: the tasks a session can run, one line each."""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from workcell.cli.command import Subparsers


def register(subparsers: Subparsers) -> None:
    parser = subparsers.add_parser(
        "tasks",
        help="list the tasks a session can run",
        description=(
            "List the built-in tasks, one line each: the name --task and task.kind take, "
            "what a trial asks, and its stages in order; then the worlds --world takes. "
            "With a module:Class, describe that task of your own (it is imported)."
        ),
    )
    parser.add_argument(
        "kind", nargs="?", metavar="module:Class", help="describe this task instead"
    )
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from workcell.tasks import WORLDS  # noqa: PLC0415
    from workcell.tasks.registry import BUILT_IN, task_class  # noqa: PLC0415

    classes = [task_class(args.kind, "tasks")] if args.kind else list(BUILT_IN.values())
    width = max(len(c.name) for c in classes)
    for task in classes:
        print(f"{task.name:<{width}}  {task.summary}; stages: {' > '.join(task.stages)}")
    print(f"\nworlds (--world): {', '.join(WORLDS)}, from narrow (D0) to broad (D2)")
    return 0

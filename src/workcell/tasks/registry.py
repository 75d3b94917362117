"""Finding a task by name: the built-in tasks, or ``module:Class`` for one of your own.

``task.kind`` (``--task``) names a built-in task (:data:`BUILT_IN`) or, as Gymnasium's
entry points do, a task class anywhere on the Python path (``my_lab.tasks:PushBox``), which
is imported when a session needs it.
"""

from __future__ import annotations

import importlib
from collections.abc import Mapping
from typing import Any

from workcell.errors import ConfigError, Problem
from workcell.tasks.box_transfer.task import BoxTransfer
from workcell.tasks.palletize.task import Palletize
from workcell.tasks.shelve.task import Shelve
from workcell.tasks.sort.task import Sort
from workcell.tasks.task import Task

BUILT_IN: dict[str, type[Task]] = {
    task.name: task for task in (BoxTransfer, Palletize, Sort, Shelve)
}
"""The tasks that come with Workcell, by name, in the order ``workcell tasks`` lists them."""
DEFAULT_TASK = BoxTransfer.name


def task_class(kind: str, key: str = "task.kind") -> type[Task]:
    """The task class ``kind`` names (raises ConfigError naming ``key`` when there is
    none)."""
    if ":" not in kind:
        found = BUILT_IN.get(kind)
        if found is None:
            raise ConfigError([_problem(key, kind, f"no such task; {_choices()}")])
        return found
    module_name, _, class_name = kind.partition(":")
    try:
        module = importlib.import_module(module_name)
    except ImportError as error:
        raise ConfigError([_problem(key, kind, f"cannot import {module_name} ({error})")]) from None
    found_class = getattr(module, class_name, None)
    if not (isinstance(found_class, type) and issubclass(found_class, Task)):
        raise ConfigError(
            [
                _problem(
                    key,
                    kind,
                    f"{module_name} has no subclass of workcell.tasks.Task named {class_name}",
                )
            ]
        )
    return found_class


def built_in_task(kind: str, key: str = "task.kind") -> type[Task]:
    """The built-in task ``kind`` names: what a client of ``workcell serve`` may start. A
    ``module:Class`` would have the server import whatever module a client names, so a
    task of one's own runs from the command line or a study file, never from a client."""
    if ":" in kind:
        raise ConfigError(
            [
                _problem(
                    key,
                    kind,
                    f"a client may start only a built-in task ({', '.join(BUILT_IN)}); a task "
                    "of your own runs with workcell collect --task or from a study file",
                )
            ]
        )
    return task_class(kind, key)


def load_task(kind: str, key: str = "task.kind") -> Task:
    """An instance of the task ``kind`` names."""
    return task_class(kind, key)()


def recorded_kind(parameters: Mapping[str, Any]) -> str:
    """The ``task.kind`` a recorded session's ``parameters`` name (box transfer for a store
    written before sessions named their task)."""
    task = parameters.get("task")
    return str(task.get("kind", DEFAULT_TASK)) if isinstance(task, Mapping) else DEFAULT_TASK


def recorded_task(parameters: Mapping[str, Any]) -> Task:
    """The task a recorded session ran (:func:`recorded_kind`)."""
    return load_task(recorded_kind(parameters))


def _choices() -> str:
    return f"the tasks are {', '.join(BUILT_IN)}, or module:Class for a task of your own"


def _problem(key: str, kind: str, allowed: str) -> Problem:
    return Problem(key, kind, allowed)

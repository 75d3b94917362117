"""Tasks: what a trial asks of the robot, one class per task, found by name
(docs/architecture.md, "Tasks"; :mod:`workcell.tasks.registry` finds them).

Importing this package loads no simulation: the command line reads the names of the worlds
from it before it knows whether it will simulate anything."""

from workcell.tasks.task import Evaluation, ObjectLook, Task, TrialJudge
from workcell.tasks.worlds import CUSTOM, WORLDS, WorldName, world_of, world_overrides

__all__ = [
    "CUSTOM",
    "WORLDS",
    "Evaluation",
    "ObjectLook",
    "Task",
    "TrialJudge",
    "WorldName",
    "world_of",
    "world_overrides",
]

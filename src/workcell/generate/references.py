"""What each stage's motion acts on: the object a segment is expressed relative to.

A task declares it (:attr:`workcell.tasks.Task.segment_references`): a segment ending at a
stage whose reference is ``box`` moves with the grasped object's pose, one whose reference
is ``goal`` with the trial's goal. A task that declares none cannot be generated yet.
"""

from __future__ import annotations

from collections.abc import Mapping

from workcell.generate.errors import GenerateError
from workcell.tasks.task import Reference, Task


def references_for(task: Task) -> Mapping[str, Reference]:
    """The reference of a segment ending at each of ``task``'s stages; a GenerateError for
    a task that declares none, or declares them for other stages than its own."""
    references = task.segment_references
    if references is None:
        raise GenerateError(
            f"--task {task.name}: the task declares no segment references "
            f"(Task.segment_references, docs/tasks.md), so generation cannot split its "
            f"trials at its stages ({' > '.join(task.stages)})"
        )
    if tuple(references) != task.stages:
        raise GenerateError(
            f"--task {task.name}: its segment references name the stages "
            f"{' > '.join(references)}, not its stages {' > '.join(task.stages)}"
        )
    return references

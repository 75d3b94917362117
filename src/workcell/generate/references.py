"""What each stage's motion acts on: the object a segment is expressed relative to.

A task declares it (:attr:`workcell.tasks.Task.segment_references`): a segment ending at a
stage whose reference is ``box`` moves with the grasped object's pose, one whose reference
is ``goal`` with the trial's goal; or, for a task carrying several boxes a trial,
:data:`~workcell.tasks.task.BY_GRASP` (segments end where the hands take or let go of a
box). A task that declares none cannot be generated yet.
"""

from __future__ import annotations

from workcell.generate.errors import GenerateError
from workcell.tasks.task import BY_GRASP, SegmentReferences, Task


def references_for(task: Task) -> SegmentReferences:
    """The reference of a segment ending at each of ``task``'s stages; a GenerateError for
    a task that declares none, or declares them for other stages than its own."""
    references = task.segment_references
    if references is None:
        raise GenerateError(
            f"--task {task.name}: the task declares no segment references "
            f"(Task.segment_references, docs/tasks.md), so generation cannot split its "
            f"trials at its stages ({' > '.join(task.stages)})"
        )
    if isinstance(references, str):
        if references != BY_GRASP:
            raise GenerateError(
                f"--task {task.name}: its segment references are {references!r}: a mapping "
                f"of its stages or {BY_GRASP!r}"
            )
        return references
    if tuple(references) != task.stages:
        raise GenerateError(
            f"--task {task.name}: its segment references name the stages "
            f"{' > '.join(references)}, not its stages {' > '.join(task.stages)}"
        )
    return references

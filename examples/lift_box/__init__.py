"""A complete minimal task: lift a box off the conveyor and hold it up.

It is loaded as ``examples.lift_box:LiftBox`` (``workcell collect --task
examples.lift_box:LiftBox``, run from the repository's root) and uses only the task API
(docs/tasks.md): box transfer's scene and expert, a judge of its own, its stages, worlds,
goal and instruction.
"""

from examples.lift_box.task import LiftBox

__all__ = ["LiftBox"]

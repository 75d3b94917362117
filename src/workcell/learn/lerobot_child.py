"""The training process of ``workcell train``: ``lerobot-train`` itself, with its log in
``OUT`` from the start.

``workcell train`` writes the training's whole output to ``OUT/train.log`` from the moment
it starts the process. LeRobot refuses an output directory that exists
(``TrainPipelineConfig.validate``), and it gets to that check only after importing torch
and its own modules: its first line came 43 s after the start on the busy 2-core machine,
which is when the log could first be made while ``OUT`` had to be new. So the process
is ``python -m workcell.learn.lerobot_child ARGS``: LeRobot's own ``main`` with
``lerobot-train``'s arguments, but for one thing: an ``OUT`` that holds nothing but that
log passes LeRobot's check of a new directory (``workcell train`` has refused any other
``OUT``). Any other existing directory is refused by LeRobot as before. The same
training on a new directory is ``lerobot-train ARGS``, which is what ``workcell train``
prints.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from workcell.learn.training_output import only_a_log


def validate_beside_the_log(check: Any) -> Any:
    """LeRobot's ``TrainPipelineConfig.validate`` (``check``), for which an output
    directory holding only ``train.log`` is new."""

    def validate(config: Any) -> None:
        out = config.output_dir
        if not (isinstance(out, Path) and only_a_log(out)):
            check(config)
            return
        config.output_dir = None  # LeRobot checks a new directory (and names a default)
        try:
            check(config)
        finally:
            config.output_dir = out

    return validate


def main() -> None:
    from lerobot.configs.train import TrainPipelineConfig  # noqa: PLC0415
    from lerobot.scripts import lerobot_train  # noqa: PLC0415

    TrainPipelineConfig.validate = validate_beside_the_log(TrainPipelineConfig.validate)
    lerobot_train.main()


if __name__ == "__main__":
    main()

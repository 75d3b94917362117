"""Registering the environments with Gymnasium (importing :mod:`workcell.envs` does it):
one id per built-in task, ``workcell/<TaskName>-v0`` (box transfer's is
``workcell/BoxTransfer-v0``), each the same environment class asked for its own task."""

from __future__ import annotations

import math

from workcell.tasks.registry import BUILT_IN

ENV_ID = "workcell/BoxTransfer-v0"
ENTRY_POINT = "workcell.envs.box_transfer:BoxTransferEnv"
FRAMES_PER_S = 20
"""The default ``recording.sampling_rate_hz``: one environment step per recorded frame."""
MAX_EPISODE_STEPS = 2400
"""Gymnasium's time limit for the default episode: 120 s at 20 frames/s (the session's
``task.time_limit_s`` and ``recording.sampling_rate_hz``). The environment truncates at
its own configured limit too; pass ``max_episode_steps`` to ``gymnasium.make`` when you
configure a longer one. A task that needs more time (:attr:`Task.least_time_limit_s`,
palletize's 180 s) is registered with that many steps."""


def env_id(task_name: str) -> str:
    """The Gymnasium id of the built-in task ``task_name``: ``box_transfer`` is
    ``workcell/BoxTransfer-v0``."""
    return "workcell/" + "".join(part.capitalize() for part in task_name.split("_")) + "-v0"


ENV_IDS: dict[str, str] = {name: env_id(name) for name in BUILT_IN}
"""Every built-in task's Gymnasium id, by task name."""


def register() -> None:
    """Register every id of :data:`ENV_IDS` with Gymnasium (doing it again changes nothing)."""
    import gymnasium  # noqa: PLC0415  (registering is the only reason to import it here)

    for name, registered_id in ENV_IDS.items():
        if registered_id not in gymnasium.registry:
            least = math.ceil(BUILT_IN[name].least_time_limit_s * FRAMES_PER_S)
            gymnasium.register(
                id=registered_id,
                entry_point=ENTRY_POINT,
                max_episode_steps=max(MAX_EPISODE_STEPS, least),
                kwargs={"task": name},
            )

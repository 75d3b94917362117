"""Registering the environment with Gymnasium (importing :mod:`workcell.envs` does it)."""

from __future__ import annotations

ENV_ID = "workcell/BoxTransfer-v0"
ENTRY_POINT = "workcell.envs.box_transfer:BoxTransferEnv"
MAX_EPISODE_STEPS = 2400
"""Gymnasium's time limit for the default episode: 120 s at 20 frames/s (the session's
``task.time_limit_s`` and ``recording.sampling_rate_hz``). The environment truncates at
its own configured limit too; pass ``max_episode_steps`` to ``gymnasium.make`` when you
configure a longer one."""


def register() -> None:
    """Register :data:`ENV_ID` with Gymnasium (doing it again changes nothing)."""
    import gymnasium  # noqa: PLC0415  (registering is the only reason to import it here)

    if ENV_ID not in gymnasium.registry:
        gymnasium.register(id=ENV_ID, entry_point=ENTRY_POINT, max_episode_steps=MAX_EPISODE_STEPS)

"""Registering the environment with Gymnasium, once, when asked."""

from __future__ import annotations

ENV_ID = "workcell/BoxTransfer-v0"
ENTRY_POINT = "workcell.envs.box_transfer:BoxTransferEnv"


def register() -> None:
    """Register :data:`ENV_ID` with Gymnasium (doing it again changes nothing)."""
    import gymnasium  # noqa: PLC0415  (registering is the only reason to import it here)

    if ENV_ID not in gymnasium.registry:
        gymnasium.register(id=ENV_ID, entry_point=ENTRY_POINT)

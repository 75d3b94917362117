"""The robomimic ``env_args`` of an HDF5 export: the environment that rebuilds a demo's
world (``gymnasium.make(env_name, **env_kwargs)``), honest about sessions that differ.

Each demo carries the ``env_args`` of its own session (its stored parameters whole). The
file-level ``env_args`` holds only the parameters every exported session shares, so it
claims no one session's settings for the whole file; ``env_args_differ`` lists the dotted
names of the settings that differ between sessions (a study's condition, its
``world.grasp``, each session's seed ...), which the environment then takes from its
defaults: read a demo's own ``env_args`` for its world.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from workcell.envs.registration import ENV_ID

ENV_NAME = ENV_ID
"""The environment that ``env_args`` names (see :mod:`workcell.envs`)."""
GYM_ENV_TYPE = 2
"""robomimic's ``EnvType.GYM_TYPE``."""


def env_args(parameters: Mapping[str, Any]) -> dict[str, Any]:
    """The ``env_args`` of a session with these stored parameters."""
    return {
        "env_name": ENV_NAME,
        "type": GYM_ENV_TYPE,
        "env_kwargs": {"session_parameters": dict(parameters)},
    }


def shared_parameters(
    sessions: Sequence[Mapping[str, Any]], prefix: str = ""
) -> tuple[dict[str, Any], list[str]]:
    """The parameters all of ``sessions`` share (tables compared setting by setting), and
    the dotted names of those that differ (or that only some sessions have)."""
    shared: dict[str, Any] = {}
    differ: list[str] = []
    keys = dict.fromkeys(key for parameters in sessions for key in parameters)
    for key in keys:
        name = f"{prefix}{key}"
        if not all(key in parameters for parameters in sessions):
            differ.append(name)
            continue
        values = [parameters[key] for parameters in sessions]
        if all(isinstance(value, Mapping) for value in values):
            inner, inner_differ = shared_parameters(values, f"{name}.")
            shared[key] = inner
            differ += inner_differ
        elif all(value == values[0] for value in values):
            shared[key] = values[0]
        else:
            differ.append(name)
    return shared, differ

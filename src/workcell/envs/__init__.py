"""Gymnasium environment of the workcell: ``workcell/BoxTransfer-v0``.

Its observation and action spaces are the exported dataset features (see
:mod:`workcell.export.features`), so a policy trained on exported demonstrations runs in
the same world, and a recorded trial's actions can be replayed in it. Importing this
package registers nothing; call :func:`register` first::

    import gymnasium
    import workcell.envs

    workcell.envs.register()
    env = gymnasium.make(workcell.envs.ENV_ID)

or let Gymnasium import the registering module:
``gymnasium.make("workcell.envs.registered:workcell/BoxTransfer-v0")``.
"""

from workcell.envs.registration import ENTRY_POINT, ENV_ID, register

__all__ = ["ENTRY_POINT", "ENV_ID", "register"]

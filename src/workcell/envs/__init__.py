"""Gymnasium environments of the workcell: ``workcell/BoxTransfer-v0`` and one
``workcell/<TaskName>-v0`` per built-in task (:data:`ENV_IDS`).

As with other Gymnasium environment packages (gym-aloha, gym-pusht), importing this
package registers the environment::

    import gymnasium
    import workcell.envs

    env = gymnasium.make("workcell/BoxTransfer-v0")

``gymnasium.make("workcell.envs:workcell/BoxTransfer-v0")`` imports it on its own.
Observations follow LeRobot's gym convention (``agent_pos``, ``environment_state``,
``pixels``): see :mod:`workcell.envs.observation`.
"""

from workcell.envs.registration import ENTRY_POINT, ENV_ID, ENV_IDS, MAX_EPISODE_STEPS, register

register()

__all__ = ["ENTRY_POINT", "ENV_ID", "ENV_IDS", "MAX_EPISODE_STEPS", "register"]

"""What the session runner needs from whoever drives the robot."""

from __future__ import annotations

from typing import Protocol

from workcell.control.command import Command
from workcell.sim.world import World


class Operator(Protocol):
    """A source of commands: the scripted expert, a teleoperation client, a replay."""

    def start_trial(self, trial_seed: int) -> None:
        """Get ready for a new trial whose world was reset with ``trial_seed``."""

    def act(self, world: World) -> Command:
        """The command for the next control period."""
        ...

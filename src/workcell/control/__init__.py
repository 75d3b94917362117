"""Robot control: the Command every operator emits and the controller that executes it."""

from workcell.control.command import ArmCommand, BaseTwist, Command

__all__ = ["ArmCommand", "BaseTwist", "Command"]

"""The operator of a session an autonomous driver runs while a person watches and may take
over: the driver's commands until the person takes control, then the person's.

The switch happens on the simulation thread, between two control periods
(:func:`workcell.intervene.switch.switch`), and never jumps the robot:

- take-over: each arm's clutch forgets its anchor and targets the pose the arm's IK
  configuration is at now (the driver's current target, as far as the arm has got), so a
  released grip holds the arm there and a held grip engages where the hand is; each
  gripper keeps the driver's closure until the person's trigger comes within
  :data:`GRIPPER_CATCH` of it (a carried box is not dropped because the trigger rests);
  the base is the person's sticks from the next period on;
- hand-back: the driver goes on from the state it finds (:meth:`Resumable.resume`: the
  scripted expert re-plans, a policy drops its queued actions).

The ``person`` is the person at a browser or headset (a
:class:`~workcell.teleop.operator.TeleopOperator`, as above) or a scripted stand-in that is
itself :class:`Resumable` (:mod:`workcell.intervene.corrector`: the task's expert), which at
a take-over goes on from the world as the driver left it, as the driver does at a hand-back.

Each trial begins with the driver driving.
"""

from __future__ import annotations

import dataclasses
from typing import Generic, Protocol, TypeVar

from workcell.control.command import Command
from workcell.recording.frame_capture import OperatorInput
from workcell.sim.world import World
from workcell.teleop.operator import TeleopOperator

GRIPPER_CATCH = 0.15
"""How close (0..1) the person's trigger must come to the closure a gripper was left at
before the trigger moves that gripper (a soft take-over, as a synthesizer's knob picks up
a value)."""


class Resumable(Protocol):
    """An autonomous operator that can go on from a state someone else left."""

    def start_trial(self, trial_seed: int) -> None: ...

    def act(self, world: World) -> Command: ...

    def resume(self, world: World, command: Command) -> None:
        """Go on from the world as it is now; ``command`` is the last one sent (the
        person's)."""


Person = TypeVar("Person", bound=TeleopOperator | Resumable)
"""Who takes over: the person at a browser or headset, or a scripted stand-in."""


class InterveningOperator(Generic[Person]):
    """Implements the task's Operator protocol: ``driver`` drives until :meth:`take_over`,
    ``person`` until :meth:`hand_back` (both on the simulation thread)."""

    def __init__(self, driver: Resumable, person: Person, driver_name: str) -> None:
        self.driver = driver
        self.person = person
        self.driver_name = driver_name
        """The driver as recorded (``expert``, ``policy:<id>``)."""
        self.person_drives = False
        """Whether the person has control (frames are corrections while they do)."""
        self.last = Command()
        """The latest command sent, whoever made it."""
        self._held_grippers = (0.0, 0.0)
        self._caught = [True, True]

    # --- the Operator protocol --------------------------------------------------------------

    def start_trial(self, trial_seed: int) -> None:
        """A new trial begins with the driver driving."""
        self.driver.start_trial(trial_seed)
        self.person.start_trial(trial_seed)
        self.person_drives = False
        self.last = Command()

    def act(self, world: World) -> Command:
        if not self.person_drives:
            self.last = self.driver.act(world)
            return self.last
        command = self.person.act(world)
        closures = [command.close_left, command.close_right]
        for side in (0, 1):
            if not self._caught[side]:
                if abs(closures[side] - self._held_grippers[side]) <= GRIPPER_CATCH:
                    self._caught[side] = True
                else:
                    closures[side] = self._held_grippers[side]
        self.last = dataclasses.replace(command, close_left=closures[0], close_right=closures[1])
        return self.last

    # --- switching --------------------------------------------------------------------------

    def take_over(self, world: World) -> bool:
        """The person drives from the next control period on; False when they already do."""
        if self.person_drives:
            return False
        person = self.person
        if isinstance(person, TeleopOperator):
            for side, clutch in person.clutches.items():
                clutch.reset()
                clutch.target = person.tcp_source(world, side)
            person.snap = None
            self._held_grippers = (self.last.close_left, self.last.close_right)
            self._caught = [False, False]
        else:  # a scripted stand-in goes on from the world as the driver left it
            person.resume(world, self.last)
            self._caught = [True, True]
        self.person_drives = True
        return True

    def hand_back(self, world: World) -> bool:
        """The driver drives again, from the state it finds; False when it already does."""
        if not self.person_drives:
            return False
        self.person_drives = False
        self.driver.resume(world, self.last)
        return True

    # --- for the recorder -------------------------------------------------------------------

    def operator_input(self) -> OperatorInput | None:
        """The person's device while they drive; None while the driver does (its frames'
        grip and trigger read from its commands, as any command-only operator's) and while a
        scripted stand-in does (it has no device)."""
        person = self.person
        if self.person_drives and isinstance(person, TeleopOperator):
            return person.operator_input()
        return None

    def intervention(self) -> bool:
        return self.person_drives

"""Demonstrations that show recoveries: the expert's base pushed off its course while it
drives, so that it steers back (noise injection, as DART does for behaviour cloning).

A policy trained on a perfect expert's demonstrations only ever sees the expert's own
states: where its base is a few centimetres off at the start of an approach, it never saw
what to do, and the error grows (``bench/README.md``, ``bench/learn_d1.py``: the policy
that never corrected a 10 cm lateral offset closed its grippers beside the box). With
``ExpertConfig.base_noise`` > 0 the twist the expert commands while it drives the base gets
a perturbation, drawn from the trial's seed and held for :data:`HOLD_S`: forward and left
speeds with standard deviation ``base_noise`` (m/s), a yaw rate with twice that (rad/s).
The perturbation is scaled by how fast the expert drives, in full from
:data:`FULL_SPEED` m/s: the expert is closed-loop (it steers toward its goal pose from
where the base is), so the record shows it correcting on its way, and it still arrives
(slowing down near its goal, it is pushed less). While the expert holds the base still
(waiting, grasping) nothing is added.

The perturbation travels as the command's ``base_push``
(:class:`~workcell.control.command.Command`): the controller executes the expert's twist
plus the push, and the frames record the expert's own twist (``cmd_vx``, ``cmd_vy``,
``cmd_wz``), as DART does: the recorded action is what the expert asked for in the state
the push led to, the correction, not the noise it was pushed with. The pushes themselves
are not recorded (they are drawn again from the trial's seed); what they did is: the base's
measured velocity (``base_vx``, ``base_vy``, ``base_wz``) against the recorded twist.

On box transfer in D1 (``bench/README.md``, issue 34), 50 demonstrations pushed at 0.1 m/s
lifted a state-only ACT from 57 to 72 % in new worlds with the push recorded in the action,
to 88 % with the expert's own action (the same states), and to 99-100 % with half-second
action chunks (``workcell train``'s default; unpushed demonstrations gain nothing from
them). At 0.15 and 0.2 the policy crawls and never grasps (one-second chunks): a chunk
holds the expert's answers to pushes not yet seen, so keep the push small against the
motion.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from workcell.control.command import BaseTwist, Command
from workcell.sim.world import World
from workcell.task.operator import Operator

HOLD_S = 0.5
"""How long one perturbation is held (s of simulated time) before the next is drawn."""
YAW_PER_SPEED = 2.0
"""The yaw rate's standard deviation (rad/s) per m/s of ``base_noise``."""
FULL_SPEED = 0.3
"""m/s (yaw rates count as half a metre's arc): from this speed on the perturbation is
added in full; below it in proportion."""
STILL = BaseTwist()
"""A base asked to stand still, which is never pushed."""
SEED_SALT = 0xDA27
"""Mixed into the trial seed, so the perturbations are not the expert's own draws."""


class Pushes:
    """The perturbations of one trial, drawn from its seed (see the module docstring)."""

    def __init__(self, trial_seed: int, base_noise: float) -> None:
        self._scale = np.array([base_noise, base_noise, YAW_PER_SPEED * base_noise])
        self._rng = np.random.default_rng((trial_seed, SEED_SALT))
        self._until = -1.0
        self._held = np.zeros(3)

    def at(self, t: float, base: BaseTwist) -> BaseTwist:
        """The perturbation at simulated time ``t`` (s) while the expert asks for ``base``;
        draws the next one once the held one has run out (only while the base drives)."""
        if base == STILL:
            return STILL
        if t >= self._until:
            self._held = self._rng.standard_normal(3) * self._scale
            self._until = t + HOLD_S
        speed = math.hypot(base.vx, base.vy) + 0.5 * abs(base.wz)
        vx, vy, wz = self._held * min(1.0, speed / FULL_SPEED)
        return BaseTwist(float(vx), float(vy), float(wz))


class NoisyBase:
    """``expert`` with its base twist perturbed while it drives (see the module docstring)."""

    def __init__(self, expert: Operator, base_noise: float) -> None:
        self.expert = expert
        self.base_noise = base_noise
        self.start_trial(0)

    def start_trial(self, trial_seed: int) -> None:
        self.expert.start_trial(trial_seed)
        self._pushes = Pushes(trial_seed, self.base_noise)

    def act(self, world: World) -> Command:
        command = self.expert.act(world)
        push = self._pushes.at(world.time, command.base)
        return command if push == STILL else dataclasses.replace(command, base_push=push)

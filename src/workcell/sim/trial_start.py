"""A trial's start from its seed: the one place that splits a trial seed into the streams
of its conditions, its feed and its task's scene, so that the running simulation
(:meth:`workcell.control.simulation.Simulation.reset`) and whoever rebuilds a recorded
trial's world (the replay) put the same world in place."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from workcell.sim.trial_conditions import TrialConditions
from workcell.sim.world import World


def start_trial(world: World, joints: NDArray[np.float64], seed: int) -> TrialConditions:
    """Reset ``world`` to the start of the trial of ``seed`` with the arms at ``joints``
    (JOINT_ORDER): the conditions drawn from ``seed`` (when randomization is on), where
    its boxes land, and what the task's scene draws (the pallet, the shelf, the tables).
    Returns the trial's conditions, with what the task's scene drew."""
    draw_stream, feed_stream, task_stream = np.random.SeedSequence(seed).spawn(3)
    conditions = TrialConditions.draw(world.config, np.random.default_rng(draw_stream))
    feed_seed = int(feed_stream.generate_state(1)[0])
    task_rng = np.random.default_rng(task_stream)
    world.reset(joints, feed_seed, conditions, task_rng)
    return world.conditions  # with what the task's scene drew, if anything

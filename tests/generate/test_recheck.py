"""The settled re-check, on a real box at rest in the real delivery zone and on a real shelf
board: a success that holds for a second passes, a box shoved off its rest or its board
within the second is caught."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from examples.lift_box.task import LiftBox

from workcell.control.command import Command
from workcell.control.simulation import Simulation
from workcell.generate.recheck import Recheck, recheck
from workcell.sim.boxes import BoxState
from workcell.sim.config import FeederConfig, WorldConfig
from workcell.sim.events import BoxCompleted
from workcell.sim.world import World
from workcell.tasks.box_transfer.task import BoxTransfer
from workcell.tasks.palletize.layout import PalletLayout
from workcell.tasks.palletize.task import Palletize
from workcell.tasks.registry import BUILT_IN, load_task
from workcell.tasks.shelve.shelf import BOARD_TOPS, ShelfLayout
from workcell.tasks.shelve.task import Shelve
from workcell.tasks.sort.judge import sort_scene
from workcell.tasks.sort.task import Sort
from workcell.tasks.task import BY_GRASP, Task


class StandStill:
    """Asks nothing of the robot."""

    def start_trial(self, trial_seed: int) -> None:
        """Nothing to prepare."""

    def act(self, world: World) -> Command:
        return Command()


class OnceHalfASecondIn(StandStill):
    """Stands still, but for ``disturb`` done to the world once, half a second in (the
    20th act)."""

    def __init__(self, disturb: Callable[[World], None]) -> None:
        self.disturb = disturb
        self.calls = 0

    def act(self, world: World) -> Command:
        self.calls += 1
        if self.calls == 20:
            self.disturb(world)
        return Command()


def _shove_delivered(world: World) -> None:
    for slot in world.boxes.slots:
        if slot.state is BoxState.DELIVERED:
            world.data.qvel[slot.qvel] = 0.6


def Shove() -> OnceHalfASecondIn:  # noqa: N802 - read like the operator it makes
    """Shoves every delivered box sideways once, half a second in."""
    return OnceHalfASecondIn(_shove_delivered)


def delivered_sim() -> Simulation:
    """A world whose only box was set down at rest in the zone and delivered."""
    sim = Simulation(WorldConfig(feeder=FeederConfig(pool_size=1)), BoxTransfer().scene())
    sim.reset(0)
    world = sim.world
    slot = world.boxes.slots[0]
    if slot.state is BoxState.PARKED:
        released = world.boxes.release(world.data, world.time)
        assert released is slot
    center = world.zone.center
    world.data.qpos[slot.qpos : slot.qpos + 3] = (center[0], center[1], world.zone.rest_z + 0.002)
    world.data.qpos[slot.qpos + 3 : slot.qpos + 7] = (1.0, 0.0, 0.0, 0.0)
    world.data.qvel[slot.qvel : slot.qvel + 6] = 0.0
    for _ in range(100):
        if any(isinstance(e, BoxCompleted) for e in sim.step(Command())):
            return sim
    raise AssertionError("the box set down in the zone was never delivered")


def test_a_settled_delivery_holds() -> None:
    sim = delivered_sim()
    check = recheck(sim, StandStill(), BoxTransfer())
    assert check.held and check.reason is None
    assert check.as_dict() == {"seconds": 1.0, "settle_s": 0.25, "held": True, "reason": None}


def test_a_box_shoved_off_its_rest_within_the_second_is_a_false_success() -> None:
    sim = delivered_sim()
    check = recheck(sim, Shove(), BoxTransfer())
    assert not check.held
    assert check.reason is not None
    assert check.reason.startswith("box 0 moving (0.")
    assert check.reason.endswith("m/s) in the zone 0.50 s after success")
    speed = np.linalg.norm(sim.world.data.qvel[sim.world.boxes.slots[0].qvel :][:2])
    assert speed > 0.06


class Bounce(StandStill):
    """Sends every delivered box up at 0.3 m/s once, at once (as a box let go of a
    centimetre above the table lands), noting the fastest it moved."""

    def __init__(self) -> None:
        self.calls = 0
        self.fastest = 0.0

    def act(self, world: World) -> Command:
        self.calls += 1
        for slot in world.boxes.slots:
            if slot.state is BoxState.DELIVERED:
                if self.calls == 1:
                    world.data.qvel[slot.qvel + 2] = 0.3
                self.fastest = max(self.fastest, world.boxes.speed(world.data, slot))
        return Command()


def test_a_box_that_bounces_once_as_it_lands_settles_and_holds() -> None:
    # the judge's rest is a moment's speed: a box let go of just above the table is
    # delivered the instant it is let go of, then lands and bounces before it rests
    sim = delivered_sim()
    bounce = Bounce()
    check = recheck(sim, bounce, BoxTransfer())
    assert bounce.fastest > 0.2
    assert check.held, check.reason


def test_a_success_with_nothing_delivered_or_a_task_without_a_check_does_not_hold() -> None:
    sim = Simulation(WorldConfig(feeder=FeederConfig(pool_size=1)), BoxTransfer().scene())
    sim.reset(0)
    check = recheck(sim, StandStill(), BoxTransfer())
    assert check == Recheck(False, "no completed object to check")
    shelve = Shelve()
    shelf_sim = Simulation(WorldConfig(), shelve.scene())
    shelf_sim.reset(0)  # its box waits on the table: nothing shelved
    check = recheck(shelf_sim, StandStill(), shelve)
    assert check == Recheck(False, "no completed object to check")
    lift = LiftBox()
    lift_sim = Simulation(WorldConfig(), lift.scene())
    lift_sim.reset(0)
    check = recheck(lift_sim, StandStill(), lift)
    assert check == Recheck(False, "the task lift_box has no settled check")


def shelved_sim() -> tuple[Simulation, ShelfLayout]:
    """A shelve world whose box was set down at rest on the asked board, and its layout."""
    sim = Simulation(WorldConfig(), Shelve().scene())
    sim.reset(3)
    world = sim.world
    layout = ShelfLayout.from_recorded(world.conditions.task_values)
    x, y = layout.board_center(layout.asked)
    z = BOARD_TOPS[layout.asked] + world.conditions.box_size[2] / 2 + 0.001
    slot = world.boxes.slots[0]
    world.data.qpos[slot.qpos : slot.qpos + 7] = (x, y, z, 1.0, 0.0, 0.0, 0.0)
    world.data.qvel[slot.qvel : slot.qvel + 6] = 0.0
    for _ in range(40):
        sim.step(Command())
    return sim, layout


def _push_off(world: World) -> None:
    for slot in world.boxes.slots:
        if slot.state is not BoxState.PARKED:
            world.data.qpos[slot.qpos : slot.qpos + 3] = (0.0, 0.0, 0.3)


def PushOff() -> OnceHalfASecondIn:  # noqa: N802 - read like the operator it makes
    """Moves every box in play off its shelf or pallet (to 0.3 m above the factory's
    origin) once, half a second in."""
    return OnceHalfASecondIn(_push_off)


def test_a_shelved_box_holds_and_one_taken_off_its_board_is_a_false_success() -> None:
    sim, layout = shelved_sim()
    check = recheck(sim, StandStill(), Shelve())
    assert check == Recheck(True)
    sim, layout = shelved_sim()
    check = recheck(sim, PushOff(), Shelve())
    assert check == Recheck(False, f"box 0 off the {layout.asked_name} board 0.50 s after success")


def test_each_tasks_segment_references_name_its_stages() -> None:
    declared = 0
    for name in BUILT_IN:
        task = load_task(name)
        references = task.segment_references
        if references is None:
            continue
        declared += 1
        assert type(task).settled_check is not Task.settled_check, name
        if isinstance(references, str):
            assert references == BY_GRASP, name
            continue
        assert tuple(references) == task.stages, name
        assert set(references.values()) <= {"box", "goal"}, name
    assert declared == 4  # every built-in task


def palletized_sim() -> Simulation:
    """A palletize world whose four boxes were set down at rest, one in each slot."""
    sim = Simulation(WorldConfig(), Palletize().scene())
    sim.reset(0)
    world = sim.world
    layout = PalletLayout.of(world.conditions.as_dict(), world.config)
    for index, slot in enumerate(world.boxes.slots[:4]):
        if slot.state is BoxState.PARKED:
            assert world.boxes.release(world.data, world.time) is slot
        x, y = layout.slot_center(index)
        world.data.qpos[slot.qpos : slot.qpos + 7] = (x, y, layout.rest_z + 0.001, 1, 0, 0, 0)
        world.data.qvel[slot.qvel : slot.qvel + 6] = 0.0
    for _ in range(40):
        sim.step(Command())
    return sim


def test_a_full_pallet_holds_and_a_box_knocked_out_of_its_slot_is_a_false_success() -> None:
    check = recheck(palletized_sim(), StandStill(), Palletize())
    assert check == Recheck(True)
    assert Palletize().settled_check(palletized_sim().world).objects == 4
    check = recheck(palletized_sim(), PushOff(), Palletize())
    assert check == Recheck(False, "box 0 out of slot 1 0.50 s after success")


def test_sort_is_settled_once_sorted_and_undone_by_a_box_missorted_after() -> None:
    sim = Simulation(WorldConfig(), Sort().scene())
    sim.reset(0)
    scene = sort_scene(sim.world)
    assert Sort().settled_check(sim.world).objects == 0
    scene.sorted_count = 4  # as if the trial had sorted its four boxes (each taken away)
    check = Sort().settled_check(sim.world)
    assert check.objects == 4 and check.why_undone(sim.world, settling=False) is None
    scene.missorted.add(2)
    assert check.why_undone(sim.world, settling=False) == "box 2 set down in the other kind's zone"

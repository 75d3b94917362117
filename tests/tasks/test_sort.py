"""The sort task: two kinds of box drawn per trial, each kind onto its own table; its
layout (recorded and observed), its settled success and its failure, its expert in D0 and
D2 with the stages in order, its environment, and collect, audit and export."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import gymnasium
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

from workcell.cli.main import main
from workcell.control.command import Command
from workcell.control.simulation import Simulation
from workcell.envs.actions import action_from_command
from workcell.envs.box_transfer import BoxTransferEnv
from workcell.envs.config import BoxTransferConfig
from workcell.errors import ConfigError
from workcell.expert.skill import ExpertConfig
from workcell.export.boxes import goal_slice
from workcell.sim.boxes import BoxSlot, BoxState
from workcell.sim.config import TargetConfig, WorldConfig
from workcell.tasks.box_transfer.task import BoxTransfer
from workcell.tasks.sort.judge import SortJudge, sort_scene
from workcell.tasks.sort.layout import SortLayout, sorting_table_center
from workcell.tasks.sort.scene import SORTED_S
from workcell.tasks.sort.task import BOXES, MAX_BOXES, SORTED_BOXES, Sort
from workcell.tasks.task import Evaluation
from workcell.tasks.worlds import randomization


def _sim(world: str = "D0") -> Simulation:
    ranges = randomization(Sort.worlds[world])  # type: ignore[index]
    return Simulation(WorldConfig(randomization=ranges), Sort().scene())


def test_each_box_takes_its_kinds_size_and_colour_and_the_layout_is_recorded() -> None:
    sim = _sim()
    world = sim.world
    conditions = sim.reset(3)
    layout = sort_scene(world).layout
    assert sorted(layout.box_kinds) == [0, 0, 1, 1]  # two of each kind, in random order
    small, large = sorted(layout.kinds, key=lambda k: k.size[0])
    assert small.size[0] < 0.9 * large.size[0] and small.mass < large.mass
    assert small.rgba != large.rgba
    for slot in world.boxes.slots:
        kind = layout.kinds[layout.kind_of(slot.index)]
        assert (2 * world.model.geom_size[slot.geom]).tolist() == pytest.approx(kind.size)
        assert world.model.geom_rgba[slot.geom].tolist() == pytest.approx(kind.rgba)
        assert world.model.body_mass[slot.body] == pytest.approx(kind.mass)
        assert world.boxes.size_of(slot) == kind.size
    # each zone wears its kind's colour; the sorting table stands where the layout says
    zone_b = world.model.geom("sorting_table_zone").id
    assert world.model.geom_rgba[zone_b][:3].tolist() == pytest.approx(layout.kinds[1].rgba[:3])
    assert layout.tables[1] == sorting_table_center(world.config) == (1.6, -1.9)
    # recorded with the trial's conditions, and read back the same
    recorded = conditions.as_dict()
    assert SortLayout.from_recorded(recorded["task"], recorded["target_center"]) == layout
    assert Sort().goal(recorded, world.config) == (
        *layout.tables[0],
        *layout.tables[1],
        *[float(k) for k in layout.box_kinds],
        *[-1.0] * (MAX_BOXES - 4),
    )
    sim.reset(3)
    assert sort_scene(world).layout == layout  # the same seed, the same trial
    sim.reset(4)
    assert sort_scene(world).layout != layout


def test_in_d1_both_tables_move_and_the_boxes_land_on_the_belt_at_their_own_height() -> None:
    sim = _sim("D1")
    world = sim.world
    seen = set()
    for seed in (1, 2):
        sim.reset(seed)
        layout = sort_scene(world).layout
        table_b = np.array(layout.tables[1])
        shift = np.abs(table_b - np.array(sorting_table_center(world.config)))
        assert 0 < shift.max() <= 0.1
        body = world.model.body("sorting_table").id
        assert world.model.body_pos[body, :2].tolist() == pytest.approx(table_b.tolist())
        seen.add(tuple(table_b))
    assert len(seen) == 2
    for _ in range(round(3.0 / world.control_dt)):
        sim.step(Command())
    (first,) = world.boxes.active()
    height = world.config.conveyor.height + world.boxes.size_of(first)[2] / 2
    assert world.boxes.position(world.data, first)[2] == pytest.approx(height, abs=0.005)


def _place(sim: Simulation, slot: BoxSlot, table: int) -> None:
    """Set ``slot``'s box down at rest on the centre of ``table``'s zone."""
    world = sim.world
    x, y = sort_scene(world).layout.tables[table]
    z = world.config.target.table_height + world.boxes.size_of(slot)[2] / 2 + 0.001
    world.data.qpos[slot.qpos : slot.qpos + 7] = (x, y, z, 1.0, 0.0, 0.0, 0.0)
    world.data.qvel[slot.qvel : slot.qvel + 6] = 0.0


def _run(sim: Simulation, judge: SortJudge, seconds: float) -> Evaluation:
    for _ in range(round(seconds / sim.world.control_dt)):
        for event in sim.step(Command()):
            judge.observe(event)
    return judge.evaluate(sim.world)


def test_a_box_is_sorted_only_once_it_has_rested_a_second_released_in_its_own_zone() -> None:
    sim = _sim()
    world = sim.world
    sim.reset(5)
    judge = Sort().new_trial(1)
    slot = world.boxes.release(world.data, world.time)
    assert slot is not None
    own = sort_scene(world).layout.kind_of(slot.index)
    _place(sim, slot, own)
    evaluation = _run(sim, judge, 0.6 * SORTED_S)
    assert (evaluation.success, judge.done, slot.state) == (False, 0, BoxState.ACTIVE)
    # knocked off the table before its second was up: it does not count
    world.data.qpos[slot.qpos : slot.qpos + 3] = (2.8, 0.0, world.boxes.size_of(slot)[2] / 2)
    evaluation = _run(sim, judge, 2 * SORTED_S)
    assert (evaluation.success, evaluation.failure, judge.done) == (False, False, 0)
    # set down again and left for a second: sorted, and taken away
    _place(sim, slot, own)
    evaluation = _run(sim, judge, SORTED_S + 0.2)
    assert evaluation == Evaluation(success=True, failure=False, progress=1.0, stage="all_sorted")
    assert judge.done == 1 and slot.state is BoxState.DELIVERED
    assert world.boxes.position(world.data, slot)[2] < 0  # parked out of sight


def test_sorted_boxes_leave_the_pool_until_every_box_is_sorted_then_it_refills() -> None:
    """Each box is fed once per round, so the boxes arrive in the layout's order; the
    judge counts each sorted box and succeeds only at the number asked."""
    sim = _sim()
    world = sim.world
    sim.reset(7)
    judge = Sort().new_trial(4)
    layout = sort_scene(world).layout
    for count in range(1, 5):
        active = world.boxes.active()
        slot = active[0] if active else world.boxes.release(world.data, world.time)
        assert slot is not None
        _place(sim, slot, layout.kind_of(slot.index))
        evaluation = _run(sim, judge, SORTED_S + 0.2)
        assert judge.done == count and evaluation.progress == pytest.approx(count / 4)
        assert evaluation.success is (count == 4)
        assert evaluation.stage == ("all_sorted" if count == 4 else "sorted_one")
        if count < 4:
            assert slot.state is BoxState.DELIVERED  # not fed again this round
    assert all(s.state is BoxState.PARKED for s in world.boxes.slots)  # the next round


def test_a_box_set_down_on_the_other_kinds_table_fails_the_trial() -> None:
    sim = _sim()
    world = sim.world
    sim.reset(6)
    judge = Sort().new_trial(1)
    slot = world.boxes.release(world.data, world.time)
    assert slot is not None
    other = 1 - sort_scene(world).layout.kind_of(slot.index)
    _place(sim, slot, other)
    evaluation = _run(sim, judge, SORTED_S + 0.2)
    assert (evaluation.success, evaluation.failure, judge.done) == (False, True, 0)
    assert sort_scene(world).missorted == {slot.index}
    assert slot.state is BoxState.ACTIVE  # it stays where it was put


@pytest.mark.parametrize(("world", "seed"), [("D0", 3), ("D2", 4)])
def test_the_expert_sorts_four_boxes_through_the_stages_in_order(world: str, seed: int) -> None:
    """The environment's staged reward pays each stage reached once, in order (a touch and
    a grasp may fall in one frame), summing to 1.0 when the fourth box is sorted; no box
    went to the other kind's table on the way."""
    config = BoxTransferConfig(required_boxes=4, time_limit_s=150.0, reward="staged")
    env = BoxTransferEnv(config, world=world, task="sort")  # type: ignore[arg-type]
    observation, info = env.reset(seed=seed)
    world_state = env.sim.world
    conditions = world_state.conditions.as_dict()
    pool = world_state.config.feeder.pool_size
    goal = observation["environment_state"][goal_slice(pool, Sort.goal_names)]
    assert goal.tolist() == pytest.approx(Sort().goal(conditions, world_state.config), abs=1e-6)
    expert = Sort().expert(ExpertConfig())
    expert.start_trial(seed)
    stages, total = [info["stage"]], 0.0
    terminated = truncated = False
    while not (terminated or truncated):
        action = action_from_command(expert.act(world_state))
        _, reward, terminated, truncated, info = env.step(action)
        total += reward
        if info["stage"] != stages[-1]:
            stages.append(info["stage"])
    env.close()
    assert terminated and info["is_success"] and info["boxes_delivered"] == 4
    assert [s for s in Sort.stages if s in stages] == stages  # in order
    assert stages[0] == "none" and stages[-1] == "all_sorted"
    assert {"lifted", "over_own_table", "sorted_one"} <= set(stages)
    assert total == pytest.approx(1.0)
    assert not sort_scene(world_state).missorted


def test_the_environment_passes_gymnasiums_checker() -> None:
    env = gymnasium.make("workcell/Sort-v0")
    assert isinstance(env.unwrapped, BoxTransferEnv) and env.unwrapped.task.name == "sort"
    check_env(env.unwrapped)
    pool = env.unwrapped.config.session.world.feeder.pool_size
    state = env.unwrapped.observation_space["environment_state"]
    # each box, the goal, then each box robot-relative and the two tables' centres
    assert state.shape == (8 * pool + len(Sort.goal_names) + 9 * pool + 2 * 2,)
    env.close()


def test_collect_in_d2_audit_and_export_carry_the_sort_instruction(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    store = tmp_path / "sort.sqlite"
    argv = ["collect", "--task", "sort", "--world", "D2", "--mode", "collection", "--trials", "2"]
    assert main([*argv, "--store", str(store), "--json"]) == 0
    rows = [json.loads(line) for line in capsys.readouterr().out.splitlines()]
    assert [r["outcome"] for r in rows] == ["success", "success"]
    assert main(["audit", "--store", str(store), "--out", str(tmp_path / "audit")]) == 0
    with (tmp_path / "audit" / "trials.csv").open() as file:
        assert [t["outcome"] for t in csv.DictReader(file)] == ["success", "success"]
    out = tmp_path / "lerobot"
    assert main(["export", "--format", "lerobot", "--store", str(store), "--out", str(out)]) == 0
    info = json.loads((out / "meta" / "info.json").read_text())
    names = info["features"]["observation.environment_state"]["names"]
    pool = sum(1 for name in names if name.startswith("box") and name.endswith("_state"))
    assert names[goal_slice(pool, Sort.goal_names)] == list(Sort.goal_names)
    asked = BOXES.format(n=SORTED_BOXES)  # every trial sorts its four boxes
    assert asked.encode() in (out / "meta" / "tasks.parquet").read_bytes()


def test_a_sorting_table_that_would_stand_on_the_delivery_table_is_one_clear_error() -> None:
    """The sorting table is the delivery table mirrored across the conveyor's centre line:
    a delivery table on that line leaves no room for it."""
    config = WorldConfig(target=TargetConfig(center=(1.6, 0.2)))
    with pytest.raises(ConfigError) as raised:
        Simulation(config, Sort().scene())
    (problem,) = raised.value.problems
    assert problem.startswith("world.target.center = ") and "sorting table" in problem
    Simulation(config, BoxTransfer().scene())  # a valid world for a task with one table

"""Shelve (src/workcell/tasks/shelve): the expert puts the box on the asked board in D0 and
D2, the judge's success is a settled box on the asked board (never a transient frame, never
a box knocked off before it settled, never the wrong board), the stages come in order, the
feeder stays idle, and a collected store is audited and exported to LeRobot with each
trial's own instruction and goal; the environment passes Gymnasium's checker."""

from __future__ import annotations

import dataclasses
import json
import math
from pathlib import Path

import gymnasium
import numpy as np
import pyarrow.parquet as pq  # type: ignore[import-untyped, unused-ignore]
import pytest
from gymnasium.utils.env_checker import check_env

import workcell.envs  # noqa: F401  (registers the environments)
from workcell.cli.main import main
from workcell.control.command import Command
from workcell.control.simulation import Simulation
from workcell.expert.skill import ExpertConfig
from workcell.export.boxes import goal_slice
from workcell.session.config import SessionConfig, TaskConfig
from workcell.sim.config import WorldConfig
from workcell.sim.events import BoxReleased
from workcell.task.runner import SessionRunner
from workcell.task.schedule import TrialSpec
from workcell.tasks.registry import BUILT_IN, load_task
from workcell.tasks.shelve.judge import ShelveJudge
from workcell.tasks.shelve.shelf import BOARD_TOPS, SHELF_NAMES, ShelfLayout
from workcell.tasks.shelve.stages import SHELVE_STAGES
from workcell.tasks.shelve.task import Shelve
from workcell.tasks.worlds import WorldName, randomization

FRAME_STEPS = 2
"""Control periods per recorded frame (40 Hz control, 20 Hz frames): the judge's clock."""
UNBOUNDED = "ignore:.*(infinity|symmetric and normalized|not having a spec).*:UserWarning"


def _world(name: WorldName) -> WorldConfig:
    return dataclasses.replace(
        SessionConfig().world, randomization=randomization(Shelve.worlds[name])
    )


def _expert_trial(sim: Simulation, seed: int) -> tuple[str, list[str], set[str]]:
    """One trial of the session runner with the expert; its outcome, its stages and the
    instructions its HUD showed."""
    task = load_task("shelve")
    config = dataclasses.replace(
        SessionConfig(world=sim.config),
        task=TaskConfig(kind="shelve", mode="practice", time_limit_s=60.0, countdown_s=0.0),
    )
    runner = SessionRunner(config, sim, task.expert(ExpertConfig()), max_trials=1)
    runner.start(TrialSpec(0, "practice", None, None, 1, 60.0), world_seed=seed)
    stages: list[str] = []
    instructions: set[str] = set()

    def seen() -> None:
        hud = runner.hud()
        instructions.add(hud.instruction)
        if not stages or stages[-1] != hud.stage:
            stages.append(hud.stage)

    (result,) = runner.run(after_step=seen)
    return result.outcome, stages, instructions


@pytest.mark.parametrize(("world", "seeds"), [("D0", (1, 2, 3)), ("D2", (1000, 1003, 1008))])
def test_the_expert_shelves_the_box_on_every_board(
    world: WorldName, seeds: tuple[int, ...]
) -> None:
    sim = Simulation(_world(world), Shelve().scene())
    asked = set()
    for seed in seeds:
        outcome, stages, instructions = _expert_trial(sim, seed)
        layout = ShelfLayout.from_recorded(sim.world.conditions.task_values)
        asked.add(layout.asked)
        # the HUD says which shelf, the same sentence the exports carry
        (instruction,) = instructions
        assert SHELF_NAMES[layout.asked] in instruction
        assert instruction == Shelve().trial_instruction(1, sim.world.conditions.as_dict())
        assert outcome == "success", (world, seed, stages)
        # the stages come in order and end settled, the box on the asked board
        order = [SHELVE_STAGES.index(s) for s in stages]
        assert order == sorted(order) and stages[-1] == "settled"
        assert {"grasped", "lifted", "placed"} <= set(stages)
        box = sim.world.boxes.position(sim.world.data, sim.world.boxes.slots[0])
        height = sim.world.conditions.box_size[2]
        assert layout.on_board(layout.asked, box, height)
    assert asked == {0, 1, 2}  # these seeds ask for each board once


def test_the_feeder_brings_nothing_and_the_box_waits_on_the_table() -> None:
    sim = Simulation(_world("D1"), Shelve().scene())
    conditions = sim.reset(5)
    table = sim.config.target.table_height
    box = sim.world.boxes.position(sim.world.data, sim.world.boxes.slots[0])
    assert box[2] == pytest.approx(table + conditions.box_size[2] / 2, abs=0.005)
    released = []
    for _ in range(int(20.0 / sim.control_dt)):
        released += [e for e in sim.step(Command()) if isinstance(e, BoxReleased)]
    assert released == [] and len(sim.world.boxes.active()) == 1
    after = sim.world.boxes.position(sim.world.data, sim.world.boxes.slots[0])
    assert np.linalg.norm(after - box) < 0.01  # still resting on the table
    recorded = conditions.as_dict()["task"]
    assert recorded["shelf"] in (0, 1, 2) and len(recorded["shelf_center"]) == 2


def _judged(sim: Simulation, judge: ShelveJudge, seconds: float) -> list[bool]:
    """Step the world with nobody acting; the judge's success at every frame instant."""
    successes = []
    for step in range(1, round(seconds / sim.control_dt) + 1):
        sim.step(Command())
        if step % FRAME_STEPS == 0:
            successes.append(judge.evaluate(sim.world).success)
    return successes


def _put(sim: Simulation, board: int, dz: float = 0.001) -> None:
    """Set the box down on ``board`` (at rest, released)."""
    world = sim.world
    layout = ShelfLayout.from_recorded(world.conditions.task_values)
    x, y = layout.board_center(board)
    z = BOARD_TOPS[board] + world.conditions.box_size[2] / 2 + dz
    slot = world.boxes.slots[0]
    world.data.qpos[slot.qpos : slot.qpos + 7] = (x, y, z, 1.0, 0.0, 0.0, 0.0)
    world.data.qvel[slot.qvel : slot.qvel + 6] = 0.0


def test_success_is_a_box_settled_on_the_asked_board_for_a_second() -> None:
    sim = Simulation(_world("D0"), Shelve().scene())
    sim.reset(3)
    asked = ShelfLayout.from_recorded(sim.world.conditions.task_values).asked
    judge = ShelveJudge()
    _put(sim, asked)
    successes = _judged(sim, judge, 1.5)
    first = successes.index(True)
    assert not any(successes[:first]) and (first + 1) * FRAME_STEPS * sim.control_dt >= 0.95
    assert judge.stage == "settled" and judge.done == 1


def test_a_transient_frame_or_a_box_knocked_off_before_it_settled_is_no_success() -> None:
    sim = Simulation(_world("D0"), Shelve().scene())
    sim.reset(3)
    layout = ShelfLayout.from_recorded(sim.world.conditions.task_values)
    judge = ShelveJudge()
    _put(sim, layout.asked)
    assert _judged(sim, judge, 0.1) == [False, False]
    assert judge.stage == "placed"  # on the board, not settled
    sim.world.boxes.park(sim.world.data, sim.world.boxes.slots[0])  # gone: one frame's worth
    sim.world.boxes.slots[0].state = sim.world.boxes.slots[0].state.ACTIVE
    assert not any(_judged(sim, judge, 0.5))
    _put(sim, layout.asked)
    assert not any(_judged(sim, judge, 0.7))
    # knocked off the board before a second was up: it lies on the floor, never a success
    slot = sim.world.boxes.slots[0]
    sim.world.data.qpos[slot.qpos : slot.qpos + 3] += (0.0, 0.8, -BOARD_TOPS[layout.asked])
    assert not any(_judged(sim, judge, 2.0))
    assert judge.stage == "placed" and judge.done == 0


def test_the_wrong_board_is_no_success() -> None:
    sim = Simulation(_world("D0"), Shelve().scene())
    sim.reset(3)
    asked = ShelfLayout.from_recorded(sim.world.conditions.task_values).asked
    judge = ShelveJudge()
    _put(sim, (asked + 1) % len(SHELF_NAMES))
    assert not any(_judged(sim, judge, 2.0))
    assert judge.stage == "none"


def test_goal_and_instruction_name_the_asked_board() -> None:
    task = Shelve()
    world = SessionConfig().world
    recorded = {"task": {"shelf": 0, "shelf_center": [1.5, -2.0]}}
    assert task.goal(recorded, world) == pytest.approx((0.65, -2.0, 0.55))
    assert task.trial_instruction(1, recorded) == "Put the box from the table on the bottom shelf."
    assert task.trial_instruction(1, {}) == "Put the box from the table on the top shelf."
    assert "shelve" in BUILT_IN


@pytest.mark.filterwarnings(UNBOUNDED)
def test_the_environment_passes_gymnasiums_checker_and_observes_the_goal() -> None:
    env = gymnasium.make("workcell/Shelve-v0", world="D1").unwrapped
    check_env(env)
    obs, _ = env.reset(seed=4)
    sim = env.sim  # type: ignore[attr-defined]
    layout = ShelfLayout.from_recorded(sim.world.conditions.task_values)
    goal = (*layout.board_center(layout.asked), BOARD_TOPS[layout.asked])
    where = goal_slice(sim.config.feeder.pool_size, Shelve.goal_names)
    assert obs["environment_state"][where] == pytest.approx(goal, abs=1e-5)
    env.close()


def test_collected_audited_and_exported_with_each_trials_instruction(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    store = tmp_path / "shelve.sqlite"
    argv = ["collect", "--task", "shelve", "--world", "D2", "--mode", "collection"]
    assert main([*argv, "--trials", "2", "--seed", "3", "--store", str(store), "--json"]) == 0
    rows = [json.loads(line) for line in capsys.readouterr().out.splitlines()]
    assert [r["outcome"] for r in rows] == ["success", "success"]
    assert main(["audit", "--store", str(store), "--out", str(tmp_path / "audit")]) == 0
    out = tmp_path / "lerobot"
    assert main(["export", "--format", "lerobot", "--store", str(store), "--out", str(out)]) == 0
    info = json.loads((out / "meta" / "info.json").read_text())
    names = info["features"]["observation.environment_state"]["names"]
    height, shelf_y = names.index("shelf_height"), names.index("shelf_y")
    assert names[height - 2 : height + 1] == ["shelf_x", "shelf_y", "shelf_height"]
    assert names[-2:] == ["shelf_in_base_x", "shelf_in_base_y"]  # the goal's point, robot-relative
    provenance = pq.read_table(out / "meta" / "workcell_provenance.parquet").to_pylist()
    tasks = {row["task"] for row in provenance}
    assert all(t.startswith("Put the box from the table on the ") for t in tasks)
    frames = pq.read_table(out / "data" / "chunk-000" / "file-000.parquet").to_pylist()
    heights = {round(row["observation.environment_state"][height], 3) for row in frames}
    named = {t.split(" on the ")[1].split()[0] for t in tasks}
    assert {SHELF_NAMES[BOARD_TOPS.index(h)] for h in heights} == named
    table = pq.read_table(out / "meta" / "tasks.parquet").to_pandas()
    assert set(table.index) == tasks
    assert not math.isnan(frames[0]["observation.environment_state"][shelf_y])

"""Palletize: four boxes from the conveyor on a pallet, 2x2. Its judge (a settled pallet,
never one transient frame), its layout and goal, its expert in D0 and in D2, collected,
audited and exported with its instruction, and its Gymnasium environment."""

from __future__ import annotations

import csv
import dataclasses
import json
from pathlib import Path

import gymnasium
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

from workcell.cli.main import main
from workcell.control.command import Command
from workcell.control.simulation import Simulation
from workcell.envs.box_transfer import BoxTransferEnv
from workcell.expert.skill import ExpertConfig
from workcell.export.boxes import goal_slice
from workcell.session.config import SessionConfig, TaskConfig
from workcell.sim.boxes import BoxState
from workcell.sim.config import WorldConfig
from workcell.task.runner import SessionRunner
from workcell.task.schedule import TrialSpec
from workcell.tasks import Evaluation, world_of
from workcell.tasks.palletize.judge import PalletizeJudge
from workcell.tasks.palletize.layout import PALLET_HEIGHT, PalletLayout
from workcell.tasks.palletize.stages import PALLETIZE_STAGES
from workcell.tasks.palletize.task import INSTRUCTION, Palletize
from workcell.tasks.registry import load_task
from workcell.tasks.worlds import randomization

LIMIT_S = 180.0
"""Palletize's time limit: four carries take the expert about 100-130 s."""
UNBOUNDED = "ignore:.*Box.*(unbounded|infinite|inf).*:UserWarning"
FRAME_STEPS = 2
"""Control periods per recorded frame (40 Hz control, 20 Hz frames)."""


def _world(name: str = "D0") -> WorldConfig:
    ranges = Palletize.worlds[name]  # type: ignore[index]
    return dataclasses.replace(WorldConfig(), randomization=randomization(ranges))


def _set_down(sim: Simulation, layout: PalletLayout, slot: int) -> int:
    """Release a box from the pool and put it at rest in ``slot``; its index."""
    world = sim.world
    box = world.boxes.release(world.data, world.time)
    assert box is not None
    x, y = layout.slot_center(slot)
    world.data.qpos[box.qpos : box.qpos + 3] = (x, y, layout.rest_z + 0.001)
    c, s = np.cos(layout.yaw / 2), np.sin(layout.yaw / 2)
    world.data.qpos[box.qpos + 3 : box.qpos + 7] = (c, 0.0, 0.0, s)
    world.data.qvel[box.qvel : box.qvel + 6] = 0.0
    return box.index


def _frames(sim: Simulation, judge: PalletizeJudge, seconds: float) -> list[Evaluation]:
    """Step the idle robot for ``seconds``, asking the judge at every frame instant."""
    evaluations = []
    for _ in range(round(seconds * 20)):
        for _ in range(FRAME_STEPS):
            for event in sim.step(Command()):
                judge.observe(event)
        evaluations.append(judge.evaluate(sim.world))
    return evaluations


@pytest.fixture(scope="module")
def idle() -> Simulation:
    return Simulation(
        WorldConfig(feeder=dataclasses.replace(WorldConfig().feeder, first_release_s=600.0)),
        Palletize().scene(),
    )


def test_a_full_pallet_succeeds_only_once_it_has_settled(idle: Simulation) -> None:
    """Four boxes at rest in four slots: ``placed_4`` at once, success only after a whole
    second of frames, and never while one of them is out of its slot."""
    idle.reset(3)
    layout = PalletLayout.of(idle.world.conditions.as_dict(), idle.config)
    judge = PalletizeJudge()
    assert judge.evaluate(idle.world).stage == "none"
    for slot in range(3):
        _set_down(idle, layout, slot)
    three = _frames(idle, judge, 0.5)
    assert [e.stage for e in three][-1] == "placed_3" and not any(e.success for e in three)
    assert three[-1].progress == pytest.approx(0.75) and judge.done == 3
    _set_down(idle, layout, 3)
    four = _frames(idle, judge, 1.5)
    first = next(i for i, e in enumerate(four) if e.success)
    assert four[0].stage == "placed_4" and not four[0].success
    assert 19 <= first <= 21  # a second of frames after the pallet filled, not one frame
    assert four[first].stage == "settled" and judge.done == 4
    assert all(b.state is BoxState.DELIVERED for b in idle.world.boxes.slots)


def test_a_box_knocked_off_the_pallet_is_not_success(idle: Simulation) -> None:
    idle.reset(4)
    layout = PalletLayout.of(idle.world.conditions.as_dict(), idle.config)
    judge = PalletizeJudge()
    boxes = [_set_down(idle, layout, slot) for slot in range(4)]
    before = _frames(idle, judge, 0.6)
    assert before[-1].stage == "placed_4" and not any(e.success for e in before)
    knocked = idle.world.boxes.slots[boxes[2]]
    x, y = layout.slot_center(2)
    idle.world.data.qpos[knocked.qpos : knocked.qpos + 3] = (x + 0.8, y, 0.2)
    after = _frames(idle, judge, 2.0)
    assert not any(e.success for e in after)
    assert after[-1].stage == "placed_4"  # the furthest reached, not the task done
    assert after[-1].progress == pytest.approx(0.75) and judge.done == 3
    assert knocked.state is BoxState.ACTIVE


def test_the_layout_and_goal_follow_the_trials_conditions() -> None:
    """The pallet moves with the drawn target shift and turns with the start's turn; its
    slots are laid out for the trial's boxes; the goal is the four slot centres."""
    config = _world("D2")
    task = Palletize()
    nominal = PalletLayout.of({}, config)
    assert nominal.height == PALLET_HEIGHT and nominal.yaw == 0.0
    slots = nominal.slot_centers()
    assert len({(round(x, 3), round(y, 3)) for x, y in slots}) == 4
    conditions = {
        "target_center": [config.target.center[0] + 0.2, config.target.center[1] - 0.1],
        "start_pose": [*config.robot.start_pose[:2], config.robot.start_pose[2] + 0.25],
        "box_size": [0.27, 0.33, 0.3],
    }
    moved = PalletLayout.of(conditions, config)
    assert moved.center == pytest.approx((nominal.center[0] + 0.2, nominal.center[1] - 0.1))
    assert moved.yaw == pytest.approx(0.25) and moved.size == (0.27, 0.33, 0.3)
    goal = task.goal(conditions, config)
    assert len(goal) == len(task.goal_names) == 8
    assert goal == pytest.approx([v for c in moved.slot_centers() for v in c])
    for index, center in enumerate(moved.slot_centers()):
        assert moved.slot_of(np.array([*center, moved.rest_z])) == index
        assert moved.slot_of(np.array([*center, moved.rest_z + 0.1])) is None
    assert moved.slot_of(np.array([*moved.center, moved.rest_z])) is None
    worlds = {name: randomization(r) for name, r in Palletize.worlds.items()}
    assert [world_of(Palletize.worlds, w) for w in worlds.values()] == ["D0", "D1", "D2"]
    d1, d2 = worlds["D1"], worlds["D2"]
    for name in ("start_shift", "target_shift", "start_yaw"):
        assert getattr(d2, name) >= 3 * getattr(d1, name) - 1e-12 > 0
    assert d2.box_size > 0 and d2.box_mass > 0


def test_the_expert_fills_the_pallet_in_d0_with_the_stages_in_order() -> None:
    task = load_task("palletize")
    world = _world("D0")
    sim = Simulation(world, task.scene())
    config = dataclasses.replace(
        SessionConfig(world=world),
        task=TaskConfig(kind="palletize", time_limit_s=LIMIT_S, countdown_s=0.0),
    )
    runner = SessionRunner(config, sim, task.expert(ExpertConfig()), max_trials=1)
    stages: list[str] = []

    def after() -> None:
        if not stages or runner.hud().stage != stages[-1]:
            stages.append(runner.hud().stage)

    runner.start(TrialSpec(0, "practice", None, None, 1, LIMIT_S), world_seed=21)
    (result,) = runner.run(after_step=after)
    assert (result.outcome, result.stage, result.boxes_done) == ("success", "settled", 4)
    assert [s for s in PALLETIZE_STAGES if s in stages] == stages  # in order, none skipped back
    assert stages[-1] == "settled" and {"placed_1", "placed_4"} <= set(stages)
    layout = PalletLayout.of(sim.world.conditions.as_dict(), sim.config)
    filled = {
        layout.slot_of(sim.world.boxes.position(sim.world.data, b)) for b in sim.world.boxes.slots
    }
    assert filled == {0, 1, 2, 3}


def test_collected_in_d2_audited_and_exported_with_its_instruction(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(["tasks", "palletize"]) == 0
    assert capsys.readouterr().out.startswith("palletize  stack four boxes")
    store = tmp_path / "pallet.sqlite"
    argv = ["collect", "--task", "palletize", "--world", "D2", "--mode", "collection"]
    limit = ["--set", f"task.time_limit_s={LIMIT_S}", "--seed", "5"]
    assert main([*argv, "--trials", "2", *limit, "--store", str(store), "--json"]) == 0
    rows = [json.loads(line) for line in capsys.readouterr().out.splitlines()]
    assert [r["outcome"] for r in rows] == ["success", "success"]
    assert [r["boxes_delivered"] for r in rows] == [4, 4]
    assert main(["audit", "--store", str(store), "--out", str(tmp_path / "audit")]) == 0
    with (tmp_path / "audit" / "trials.csv").open() as file:
        audited = list(csv.DictReader(file))
    assert [t["outcome"] for t in audited] == ["success", "success"]
    out = tmp_path / "lerobot"
    assert main(["export", "--format", "lerobot", "--store", str(store), "--out", str(out)]) == 0
    info = json.loads((out / "meta" / "info.json").read_text())
    names = info["features"]["observation.environment_state"]["names"]
    start = names.index("slot_1_x")
    assert names[start : start + 8] == list(Palletize.goal_names)
    assert names[-8:] == [f"slot_{i}_in_base_{a}" for i in range(1, 5) for a in "xy"]
    assert INSTRUCTION.encode() in (out / "meta" / "tasks.parquet").read_bytes()


@pytest.mark.filterwarnings(UNBOUNDED)
def test_its_environment_passes_gymnasiums_checker() -> None:
    env = gymnasium.make("workcell/Palletize-v0")
    unwrapped = env.unwrapped
    assert isinstance(unwrapped, BoxTransferEnv) and unwrapped.task.name == "palletize"
    check_env(unwrapped)
    observation, info = unwrapped.reset(seed=2)
    assert info["stage"] == "none"
    layout = PalletLayout.of(unwrapped.sim.world.conditions.as_dict(), unwrapped.sim.config)
    pool = unwrapped.sim.config.feeder.pool_size
    goal = observation["environment_state"][goal_slice(pool, Palletize.goal_names)]
    assert goal.tolist() == pytest.approx([v for c in layout.slot_centers() for v in c], abs=1e-5)
    env.close()

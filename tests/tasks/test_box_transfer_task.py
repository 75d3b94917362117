"""Box transfer on the task API: its worlds, its one success rule and its stages, judged
live exactly as the audit reads them back from the recorded frames."""

from __future__ import annotations

import json
import sqlite3
from dataclasses import replace
from pathlib import Path

import pyarrow.parquet as pq  # type: ignore[import-untyped, unused-ignore]
import pytest

from workcell.audit.run import run_audit
from workcell.audit.store_source import StoreSource
from workcell.cli.main import main
from workcell.envs.actions import action_from_command
from workcell.envs.box_transfer import BoxTransferEnv
from workcell.envs.config import BoxTransferConfig
from workcell.errors import ConfigError
from workcell.expert.skill import ExpertConfig
from workcell.export.boxes import goal_slice
from workcell.recording.drivers import ExpertDriver
from workcell.recording.headless import run_headless
from workcell.recording.recorded_session import RecordedSession, RecordedSessionConfig
from workcell.session.config import SessionConfig, TaskConfig
from workcell.sim.randomization import RandomizationConfig
from workcell.task.runner import TrialResult
from workcell.tasks import CUSTOM, world_of
from workcell.tasks.box_transfer.task import BoxTransfer
from workcell.tasks.elements.expert import ExpertOperator


def test_the_worlds_widen_from_d0_to_d2() -> None:
    worlds = {name: RandomizationConfig(**ranges) for name, ranges in BoxTransfer.worlds.items()}
    assert worlds["D0"] == RandomizationConfig()
    d1, d2 = worlds["D1"], worlds["D2"]
    assert (d1.start_shift, d1.target_shift, d1.start_yaw) == (0.1, 0.1, 0.1)
    for name in ("start_shift", "target_shift", "start_yaw"):
        assert getattr(d2, name) >= 3 * getattr(d1, name) - 1e-12
    assert d2.box_size > 0 and d2.box_mass > 0 and d1.box_size == 0
    assert [world_of(BoxTransfer.worlds, w) for w in worlds.values()] == ["D0", "D1", "D2"]
    assert world_of(BoxTransfer.worlds, RandomizationConfig(start_shift=0.2)) == CUSTOM
    # every world is a valid one for the default session
    for section in worlds.values():
        SessionConfig(world=replace(SessionConfig().world, randomization=section))


def _parameters(store: Path) -> dict[str, object]:
    with sqlite3.connect(store) as connection:
        (text,) = connection.execute("SELECT parameters_json FROM sessions").fetchone()
    parameters: dict[str, object] = json.loads(text)
    return parameters


def test_collect_in_a_world_records_its_ranges_and_draws_from_them(tmp_path: Path) -> None:
    store = tmp_path / "d1.sqlite"
    argv = ["collect", "--task", "box_transfer", "--world", "D1", "--mode", "collection"]
    assert main([*argv, "--trials", "2", "--seed", "7", "--store", str(store)]) == 0
    parameters = _parameters(store)
    assert parameters["task"]["kind"] == "box_transfer"  # type: ignore[index]
    stored = RandomizationConfig(**parameters["world"]["randomization"])  # type: ignore[index]
    assert world_of(BoxTransfer.worlds, stored) == "D1"
    with sqlite3.connect(store) as connection:
        payloads = connection.execute(
            "SELECT payload_json FROM events WHERE kind = 'trial_started' ORDER BY seq"
        ).fetchall()
    starts = [json.loads(p)["conditions"]["start_pose"] for (p,) in payloads]
    nominal = SessionConfig().world.robot.start_pose
    for start in starts:
        assert 0 < max(abs(a - b) for a, b in zip(start[:2], nominal[:2], strict=True)) <= 0.1
    assert starts[0] != starts[1]


def _run(config: SessionConfig, store: Path, skill: float = 1.0) -> list[TrialResult]:
    recorded = RecordedSessionConfig(
        session=config, driver=ExpertDriver(ExpertConfig(skill=skill)), store=store, writer="inline"
    )
    results: list[TrialResult] = []
    with RecordedSession.open(recorded) as session:
        run_headless(session, results.append)
    return results


STAGE_AT_LIMIT = {5.0: "none", 15.5: "grasped", 17.0: "lifted", 21.0: "over_zone"}
"""Where the expert's trial of seed 11 stands when its time runs out."""


@pytest.mark.parametrize("limit_s", [*STAGE_AT_LIMIT, 120.0])
def test_the_live_stage_is_the_stage_the_audit_reads_from_the_frames(
    limit_s: float, tmp_path: Path
) -> None:
    """Trials cut short at different moments of the expert's work reach different stages;
    the task's judge says the same stage while the trial runs as the audit reads back."""
    config = SessionConfig(task=TaskConfig(time_limit_s=limit_s), seed=11)
    store = tmp_path / "s.sqlite"
    (result,) = _run(config, store)
    source = StoreSource(store)
    try:
        (audited,) = run_audit(source).trials
    finally:
        source.close()
    assert result.stage == audited.task_stage
    assert result.stage in BoxTransfer.stages
    if limit_s == 120.0:
        assert (result.outcome, result.stage) == ("success", "delivered")
    else:
        assert (result.outcome, result.stage) == ("timeout", STAGE_AT_LIMIT[limit_s])


def test_the_environment_rewards_each_stage_once_from_the_tasks_judge() -> None:
    """With staged rewards, every stage the expert reaches earns its share once; the
    stages come in order and the episode's rewards sum to 1.0 at delivery."""
    env = BoxTransferEnv(BoxTransferConfig(reward="staged"))
    _, info = env.reset(seed=5)
    assert info["stage"] == "none"
    expert = ExpertOperator(seed=5)
    stages, total = [info["stage"]], 0.0
    terminated = truncated = False
    while not (terminated or truncated):
        action = action_from_command(expert.act(env.sim.world))
        _, reward, terminated, truncated, info = env.step(action)
        total += reward
        if info["stage"] != stages[-1]:
            stages.append(info["stage"])
            assert reward > 0
        else:
            assert reward == 0.0
    env.close()
    assert terminated and info["is_success"]
    assert [s for s in BoxTransfer.stages if s in stages] == stages  # in order
    assert stages[0] == "none" and stages[-1] == "delivered" and "lifted" in stages
    assert total == pytest.approx(1.0)
    with pytest.raises(ConfigError, match="reward = 'dense': must be one of deliveries, staged"):
        BoxTransferConfig(reward="dense")  # type: ignore[arg-type]


def test_the_goal_is_observed_and_exported_where_the_trial_put_the_zone(tmp_path: Path) -> None:
    """The environment state ends with the task's goal (the zone's centre), read from the
    trial's conditions: in D1 it moves with the zone, in the env and in the export alike."""
    env = BoxTransferEnv(world="D1")
    seen = set()
    for seed in (1, 2):
        observation, _ = env.reset(seed=seed)
        center = env.sim.world.conditions.target_center
        pool = env.sim.config.feeder.pool_size
        goal = observation["environment_state"][goal_slice(pool, BoxTransfer.goal_names)]
        assert goal.tolist() == pytest.approx(center, abs=1e-6)
        seen.add(tuple(goal.tolist()))
    env.close()
    assert len(seen) == 2
    store, out = tmp_path / "d1.sqlite", tmp_path / "lerobot"
    argv = ["collect", "--world", "D1", "--mode", "collection", "--trials", "2", "--seed", "9"]
    assert main([*argv, "--store", str(store)]) == 0
    assert main(["export", "--format", "lerobot", "--store", str(store), "--out", str(out)]) == 0
    with sqlite3.connect(store) as connection:
        payloads = connection.execute(
            "SELECT payload_json FROM events WHERE kind = 'trial_started' ORDER BY seq"
        ).fetchall()
    centers = [json.loads(p)["conditions"]["target_center"] for (p,) in payloads]
    table = pq.read_table(out / "data/chunk-000/file-000.parquet").to_pydict()
    for episode, center in enumerate(centers):
        rows = [
            state[goal_slice(4, BoxTransfer.goal_names)]
            for state, index in zip(
                table["observation.environment_state"], table["episode_index"], strict=True
            )
            if index == episode
        ]
        assert rows and all(r == pytest.approx(center, abs=1e-6) for r in rows)
    assert centers[0] != centers[1]

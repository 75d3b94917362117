"""The task state machine on the real simulation: clocks, resets, modes, events."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from workcell.control.command import Command
from workcell.control.simulation import Simulation
from workcell.expert import ExpertConfig
from workcell.session.config import SessionConfig, TaskConfig
from workcell.sim.world import World
from workcell.task import events as ev
from workcell.task.bus import EventBus
from workcell.task.hud import HudPhase
from workcell.task.operator import Operator
from workcell.task.runner import SessionRunner, trial_seed
from workcell.tasks.box_transfer.task import BoxTransfer
from workcell.tasks.elements.expert import ExpertOperator


class IdleOperator:
    """Never moves: every trial times out. Remembers the world state at each trial start."""

    def __init__(self) -> None:
        self.starts: list[int] = []

    def start_trial(self, trial_seed: int) -> None:
        self.starts.append(trial_seed)

    def act(self, world: World) -> Command:
        return Command()


def make_runner(
    task: TaskConfig, operator: Operator | None = None, seed: int = 0
) -> tuple[SessionRunner, list[ev.TaskEvent]]:
    config = SessionConfig(task=task, seed=seed)
    bus = EventBus()
    seen: list[ev.TaskEvent] = []
    bus.subscribe(seen.append)
    runner = SessionRunner(
        config, Simulation(config.world, BoxTransfer().scene()), operator or IdleOperator(), bus
    )
    return runner, seen


def test_timeout_fires_exactly_at_the_limit_on_the_sim_clock() -> None:
    runner, seen = make_runner(TaskConfig(mode="practice", time_limit_s=2.0, countdown_s=0.5))
    runner.run()
    (result,) = runner.results
    assert result.outcome == "timeout"
    assert result.elapsed_s == 2.0  # exact: counted in physics steps from the clock start
    assert result.score == 0
    timed_out = [e for e in seen if isinstance(e, ev.TrialTimedOut)]
    assert [e.t_sim for e in timed_out] == [2.0]
    # the clock started after the countdown: 0.5 s + 2 s of physics in total
    assert runner.sim.world.physics_steps * runner.config.world.timestep == pytest.approx(2.5)


def test_a_trial_publishes_its_lifecycle_in_order() -> None:
    runner, seen = make_runner(TaskConfig(mode="practice", time_limit_s=1.0))
    runner.run()
    kinds = [ev.event_kind(e) for e in seen]
    assert kinds[0] == "countdown_started"
    assert (
        kinds.index("trial_started") < kinds.index("trial_timed_out") < kinds.index("trial_ended")
    )
    assert kinds[-1] == "trial_ended"
    countdown = next(e for e in seen if isinstance(e, ev.CountdownStarted))
    assert countdown.t_sim == -3.0  # the default countdown, before the clock starts
    released = [e for e in seen if isinstance(e, ev.BoxReleased)]
    assert released and released[0].t_sim == pytest.approx(0.5 - 3.0)


def test_collection_resets_the_world_for_every_trial() -> None:
    operator = IdleOperator()
    runner, seen = make_runner(
        TaskConfig(mode="collection", trials=3, time_limit_s=1.0, countdown_s=0.0), operator
    )
    starts: list[np.ndarray] = []
    bus_unsub = runner.bus.subscribe(
        lambda e: (
            starts.append(runner.sim.world.data.qpos.copy())
            if isinstance(e, ev.TrialStarted)
            else None
        )
    )
    runner.run()
    bus_unsub()
    assert [r.spec.trial_index for r in runner.results] == [0, 1, 2]
    assert all(r.outcome == "timeout" for r in runner.results)
    assert operator.starts == [trial_seed(0, i) for i in range(3)]
    # every trial starts from a fresh world: robot at its start pose, boxes parked
    base = runner.sim.world._base_qpos
    for qpos in starts:
        np.testing.assert_allclose(qpos[base], runner.config.world.robot.start_pose)
    assert len({e.trial_index for e in seen if isinstance(e, ev.TrialStarted)}) == 3


def test_identical_seeds_give_identical_trial_starts() -> None:
    def box_positions(seed: int, trial: int) -> np.ndarray:
        runner, _ = make_runner(
            TaskConfig(mode="collection", trials=trial + 1, time_limit_s=3.0), seed=seed
        )
        runner.run()
        return np.array(runner.sim.world.data.qpos, dtype=float)

    same = box_positions(11, 1), box_positions(11, 1)
    np.testing.assert_array_equal(same[0], same[1])
    assert not np.array_equal(box_positions(11, 1), box_positions(12, 1))
    assert trial_seed(11, 1) == trial_seed(11, 1) != trial_seed(11, 2)


def test_interruption_ends_the_trial_and_the_session() -> None:
    runner, seen = make_runner(TaskConfig(mode="collection", trials=5, countdown_s=0.0))
    runner.start()
    for _ in range(40):  # one second
        runner.step()
    runner.interrupt("operator_stop")
    (result,) = runner.results
    assert (result.outcome, result.interruption_reason) == ("interrupted", "operator_stop")
    assert result.elapsed_s == pytest.approx(1.0)
    assert runner.phase is HudPhase.FINISHED
    assert isinstance(seen[-1], ev.TrialEnded) and seen[-1].outcome == "interrupted"
    assert any(isinstance(e, ev.TrialInterrupted) and e.reason == "operator_stop" for e in seen)


def test_an_interruption_in_a_countdown_ends_the_session_with_no_trial() -> None:
    """A trial counting down has not started: the store keeps no row of it, so the
    runner keeps no result of it either (what collect prints is what is stored)."""
    runner, seen = make_runner(TaskConfig(mode="collection", trials=5, countdown_s=1.0))
    runner.start()
    for _ in range(20):  # half the countdown
        runner.step()
    assert runner.hud().phase is HudPhase.COUNTDOWN
    runner.interrupt("operator_stop")
    assert runner.phase is HudPhase.FINISHED
    assert runner.results == []
    assert not any(isinstance(e, ev.TrialInterrupted | ev.TrialEnded) for e in seen)


def test_five_trial_collection_with_the_expert() -> None:
    runner, seen = make_runner(TaskConfig(mode="collection", trials=5), ExpertOperator())
    results = runner.run()
    assert len(results) == 5
    assert all(r.outcome == "success" for r in results)
    for r in results:
        assert r.completion_time_s == r.elapsed_s < 120.0
        assert r.score == 100 + int(np.ceil(120.0 - r.elapsed_s - 1e-9))
    delivered = [e for e in seen if isinstance(e, ev.BoxDelivered)]
    assert [e.trial_index for e in delivered] == [0, 1, 2, 3, 4]


@pytest.mark.slow
def test_full_default_challenge_campaign_with_the_expert() -> None:
    runner, seen = make_runner(TaskConfig(mode="challenge"), ExpertOperator())
    results = runner.run()
    passed = [(r.spec.round, r.spec.level) for r in results if r.outcome == "success"]
    assert passed == [(r, lv) for r in range(1, 6) for lv in range(1, 4)]
    for r in results:
        assert r.boxes_done == r.spec.required_boxes or r.outcome == "timeout"
    changes = [e for e in seen if isinstance(e, ev.LevelChanged)]
    assert len(changes) == len(results) - 1
    assert runner.phase is HudPhase.FINISHED and not runner.capped
    assert runner.campaign_complete


@pytest.mark.slow
def test_low_skill_challenge_retries_a_timed_out_level() -> None:
    runner, seen = make_runner(
        TaskConfig(mode="challenge", rounds=1, level_time_limits_s=(40.0, 30.0, 30.0)),
        ExpertOperator(ExpertConfig(skill=0.2)),
        seed=3,
    )
    runner.max_trials = 4
    results = runner.run()
    assert any(r.outcome == "timeout" for r in results)
    for before, after in itertools.pairwise(results):
        same_level = (before.spec.round, before.spec.level) == (after.spec.round, after.spec.level)
        assert same_level == (before.outcome == "timeout")
    repeats = [e for e in seen if isinstance(e, ev.LevelChanged) and e.repeat]
    assert len(repeats) == sum(r.outcome == "timeout" for r in results[:-1])

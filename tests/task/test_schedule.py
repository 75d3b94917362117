"""Mode progression, including property tests of challenge campaigns."""

from __future__ import annotations

from hypothesis import given, settings
from hypothesis import strategies as st

from workcell.session.config import Mode, TaskConfig
from workcell.task.events import Outcome
from workcell.task.schedule import Schedule, TrialSpec


def test_practice_is_one_trial_with_one_box() -> None:
    schedule = Schedule(TaskConfig(mode="practice"))
    first = schedule.first()
    assert (first.required_boxes, first.time_limit_s, first.round, first.level) == (
        1,
        120.0,
        None,
        None,
    )
    assert schedule.next(first, "success") is None
    assert schedule.next(first, "timeout") is None


def test_collection_runs_n_one_box_trials_whatever_the_outcome() -> None:
    schedule = Schedule(TaskConfig(mode="collection", trials=4))
    spec: TrialSpec | None = schedule.first()
    outcomes: list[Outcome] = ["timeout", "success", "timeout", "success"]
    seen = []
    for outcome in outcomes:
        assert spec is not None
        seen.append(spec)
        spec = schedule.next(spec, outcome)
    assert spec is None
    assert [s.trial_index for s in seen] == [0, 1, 2, 3]
    assert all(s.required_boxes == 1 and s.time_limit_s == 120.0 for s in seen)


def test_collection_without_a_count_runs_until_stopped() -> None:
    schedule = Schedule(TaskConfig(mode="collection", trials=0))
    spec = schedule.first()
    for _ in range(500):
        following = schedule.next(spec, "success")
        assert following is not None
        spec = following
    assert schedule.next(spec, "interrupted") is None


def test_default_challenge_levels() -> None:
    schedule = Schedule(TaskConfig(mode="challenge"))
    spec: TrialSpec | None = schedule.first()
    levels = []
    while spec is not None:
        levels.append((spec.round, spec.level, spec.required_boxes, spec.time_limit_s))
        spec = schedule.next(spec, "success")
    assert len(levels) == 15
    assert levels[:3] == [(1, 1, 1, 120.0), (1, 2, 2, 100.0), (1, 3, 3, 90.0)]
    assert levels[-1] == (5, 3, 3, 90.0)


@settings(max_examples=200, deadline=None)
@given(
    rounds=st.integers(1, 4),
    levels=st.integers(1, 4),
    outcomes=st.lists(st.sampled_from(["success", "timeout"]), min_size=1, max_size=80),
)
def test_challenge_progression(rounds: int, levels: int, outcomes: list[Outcome]) -> None:
    task = TaskConfig(
        mode="challenge",
        rounds=rounds,
        level_boxes=tuple(range(1, levels + 1)),
        level_time_limits_s=tuple(100.0 - 5 * i for i in range(levels)),
    )
    schedule = Schedule(task)
    spec: TrialSpec | None = schedule.first()
    successes = 0
    for index, outcome in enumerate(outcomes):
        if spec is None:
            # The campaign ended exactly when every level of every round was passed once.
            assert successes == rounds * levels
            return
        assert spec.trial_index == index
        assert spec.round is not None and spec.level is not None
        assert 1 <= spec.round <= rounds and 1 <= spec.level <= levels
        # the level's requirements come from the configuration
        assert spec.required_boxes == task.level_boxes[spec.level - 1]
        assert spec.time_limit_s == task.level_time_limits_s[spec.level - 1]
        # progress so far decides where we are: one level per success, in order
        assert (spec.round - 1) * levels + (spec.level - 1) == successes
        following = schedule.next(spec, outcome)
        if outcome == "timeout":
            assert following is not None
            assert (following.round, following.level) == (spec.round, spec.level)
        else:
            successes += 1
        spec = following
    if spec is None:
        assert successes == rounds * levels
    else:
        assert successes < rounds * levels


@given(st.integers(1, 3), st.integers(0, 10))
def test_interruption_ends_every_mode(rounds: int, skip: int) -> None:
    modes: tuple[Mode, ...] = ("practice", "collection", "challenge")
    for mode in modes:
        schedule = Schedule(TaskConfig(mode=mode, rounds=rounds))
        spec = schedule.first()
        for _ in range(skip):
            following = schedule.next(spec, "timeout")
            if following is None:
                break
            spec = following
        assert schedule.next(spec, "interrupted") is None


def test_only_a_success_at_the_last_level_of_the_last_round_completes_a_campaign() -> None:
    schedule = Schedule(TaskConfig(mode="challenge", rounds=2))
    last = TrialSpec(9, "challenge", 2, 3, 3, 90.0)
    assert schedule.completes(last, "success")
    assert not schedule.completes(last, "timeout")
    assert not schedule.completes(last, "interrupted")
    assert not schedule.completes(TrialSpec(8, "challenge", 2, 2, 2, 100.0), "success")
    assert not schedule.completes(TrialSpec(5, "challenge", 1, 3, 3, 90.0), "success")
    collection = Schedule(TaskConfig(mode="collection", trials=1))
    assert not collection.completes(TrialSpec(0, "collection", None, None, 1, 120.0), "success")

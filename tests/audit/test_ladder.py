"""The generalization ladder's rungs (audit/ladder.py), from trials as the audit reads them."""

from __future__ import annotations

import math

from workcell.audit.ladder import LadderTrial, climbs, ladder
from workcell.metrics import wilson_interval


def _trial(
    world: str | None,
    outcome: str | None,
    time_s: float | None = None,
    stage: str | None = None,
    operator: str = "policy-act-1",
) -> LadderTrial:
    return LadderTrial(operator, "box_transfer", world, outcome, time_s, stage)


def test_a_rung_counts_complete_rollouts_and_their_stages() -> None:
    trials = [
        _trial("D1", "success", 20.0, "delivered"),
        _trial("D1", "timeout", None, "lifted"),
        _trial("D1", "success", 24.0, "delivered"),
        _trial("D1", "interrupted", None, "touched"),  # counted apart
        _trial("D1", "failed", None, "over_zone"),
        _trial("D1", "success", 30.0, "delivered"),
    ]
    (rung,) = ladder(trials)
    assert (rung.world, rung.rollouts, rung.successes, rung.interrupted) == ("D1", 5, 3, 1)
    assert rung.rate == 3 / 5 and (rung.low, rung.high) == wilson_interval(3, 5)
    assert rung.median_completion_s == 24.0
    assert rung.stages == {
        "none": 0, "touched": 0, "grasped": 0, "lifted": 1, "over_zone": 1, "delivered": 3
    }  # fmt: skip


def test_worlds_go_narrow_to_broad_and_unnamed_ranges_stay_off() -> None:
    trials = [
        _trial("D2", "timeout", stage="none"),
        _trial(None, "success", 21.0, "delivered"),  # ranges of no named world
        _trial("D0", "success", 21.0, "delivered"),
        _trial("D2", "timeout", stage="none", operator="expert"),
    ]
    rungs = ladder(trials)
    assert [(r.operator, r.world) for r in rungs] == [
        ("policy-act-1", "D0"),
        ("policy-act-1", "D2"),
        ("expert", "D2"),
    ]
    assert rungs[1].successes == 0 and math.isnan(rungs[1].median_completion_s)
    assert climbs(rungs)  # the policy ran in two worlds


def test_one_world_per_operator_is_no_ladder() -> None:
    rungs = ladder(
        [_trial("D0", "success", 21.0, "delivered"), _trial("D1", "timeout", operator="x")]
    )
    assert len(rungs) == 2 and not climbs(rungs)
    only_interrupted = ladder([_trial("D0", "interrupted")])
    assert only_interrupted[0].rollouts == 0 and math.isnan(only_interrupted[0].rate)

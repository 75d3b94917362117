"""Dispositions follow the paper's Fig. 4 on a constructed set, reviewer decisions
override the automatic rules and are shown as such, and flags never change outcomes."""

from __future__ import annotations

from tests.audit.conftest import Scenario
from workcell.audit.counts import DispositionCounts
from workcell.audit.disposition import (
    EXCLUDED_BY_REVIEWER,
    EXCLUDED_INCOMPLETE,
    EXCLUDED_LOW_QUALITY,
    VALID_SUCCESS,
    VALID_TIMEOUT,
)
from workcell.audit.findings import REVIEW
from workcell.audit.run import AuditResult
from workcell.record import Store


def test_every_case_lands_where_fig_4_puts_it(
    scenario: Scenario, scenario_audit: AuditResult
) -> None:
    by_id = {t.trial_id: t for t in scenario_audit.trials}
    stage = {name: by_id[i].disposition.stage for name, i in scenario.ids.items()}
    assert stage == {
        "clean": VALID_SUCCESS,
        "reviewer_excluded": EXCLUDED_BY_REVIEWER,
        "oscillating": EXCLUDED_LOW_QUALITY,
        "reviewer_included": VALID_SUCCESS,
        "oscillating_timeout": VALID_TIMEOUT,
        "timeout": VALID_TIMEOUT,
        "quit": EXCLUDED_INCOMPLETE,
        "crashed": EXCLUDED_INCOMPLETE,
        "gap": VALID_SUCCESS,
    }
    flags = {name: [f.name for f in by_id[i].flags] for name, i in scenario.ids.items()}
    assert flags["oscillating"] == ["arm_oscillation"]
    assert flags["oscillating_timeout"] == ["arm_oscillation"]
    assert flags["gap"] == ["sampling_gap"]
    assert flags["clean"] == flags["timeout"] == flags["quit"] == []
    marked = {name for name, i in scenario.ids.items() if by_id[i].disposition.marked}
    assert marked == {"oscillating_timeout", "reviewer_included", "gap"}
    reason = {name: by_id[i].disposition.exclusion_reason for name, i in scenario.ids.items()}
    assert reason["oscillating"] == "low quality: arm_oscillation"
    assert reason["quit"] == "incomplete: interrupted (application_quit)"
    assert reason["reviewer_excluded"] == "excluded by reviewer ana: operator was distracted"


def test_the_flow_counts(scenario_audit: AuditResult) -> None:
    c = DispositionCounts.of(scenario_audit.trials)
    assert (c.raw, c.incomplete, c.complete) == (9, 2, 7)
    assert c.incomplete_causes == {"application_quit": 1, "crash_recovered": 1}
    assert (c.complete_successes, c.complete_timeouts) == (5, 2)
    assert (c.excluded_low_quality, c.low_quality_causes) == (1, {"arm_oscillation": 1})
    assert (c.excluded_by_reviewer, c.included_by_reviewer) == (1, 1)
    assert (c.valid, c.valid_successes, c.valid_timeouts) == (5, 3, 2)
    assert (c.marked_successes, c.marked_timeouts) == (2, 1)


def test_reviewer_decisions_are_shown_as_such(
    scenario: Scenario, scenario_audit: AuditResult
) -> None:
    by_id = {t.trial_id: t for t in scenario_audit.trials}
    included = by_id[scenario.ids["reviewer_included"]].disposition
    assert included.overridden and not included.automatic_included
    assert included.automatic_reason == "low quality: arm_oscillation"
    assert included.review is not None
    assert (included.review.by, included.review.reason) == ("ben", "wobble is the conveyor's")
    crashed = by_id[scenario.ids["crashed"]].disposition
    assert not crashed.included and not crashed.overridden
    assert crashed.refused == "include by ben not applied: an interrupted trial has no outcome"
    clean = by_id[scenario.ids["clean"]].disposition
    assert clean.review is None  # a note does not decide
    reviews = {(f.trial_id, f.subject) for f in scenario_audit.findings if f.kind == REVIEW}
    assert reviews == {
        (scenario.ids["reviewer_excluded"], "exclude"),
        (scenario.ids["reviewer_included"], "include"),
        (scenario.ids["crashed"], "refused"),
    }


def test_flags_never_change_outcomes_and_raw_rows_are_untouched(
    scenario: Scenario, scenario_audit: AuditResult
) -> None:
    with Store.open(scenario.path, writer=False) as store:
        stored = {t.trial_id: t for t in store.trials()}
    for trial in scenario_audit.trials:
        row = stored[trial.trial_id]
        assert trial.row.outcome == row.outcome
        assert row.quality_flags == ()  # the audit wrote nothing back
        assert row.included == (row.outcome != "interrupted")

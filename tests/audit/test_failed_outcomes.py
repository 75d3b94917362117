"""Trials a task's judge ended ``failed`` (palletize's box off the pallet, say) are valid
failures the audit shows apart from timeouts: in the counts, in the disposition figure's
box and as a bar of their own in the outcomes figure; a store without them draws as
before."""

from __future__ import annotations

from pathlib import Path

from tests.audit import synthetic
from workcell.audit.counts import DispositionCounts
from workcell.audit.figures.flow import failures_text
from workcell.audit.figures.outcomes import draw_outcomes, outcome_bars
from workcell.audit.run import AuditResult, run_audit
from workcell.audit.stats import SuccessRate
from workcell.audit.store_source import StoreSource

PNG = b"\x89PNG\r\n\x1a\n"


def _audit(path: Path, outcomes: list[str]) -> AuditResult:
    synthetic.fill(path, outcomes, n_frames=30)
    source = StoreSource(path)
    try:
        return run_audit(source)
    finally:
        source.close()


def test_failed_trials_are_counted_and_drawn_apart_from_timeouts(tmp_path: Path) -> None:
    result = _audit(tmp_path / "s.sqlite", ["success"] * 3 + ["timeout"] * 2 + ["failed"] * 4)
    counts = DispositionCounts.of(result.trials)
    rate = SuccessRate.of(result.trials)
    assert (rate.successes, rate.n) == (3, 9)
    assert (counts.valid_timeouts, counts.valid_failures, counts.complete_failures) == (2, 4, 4)
    assert [(name, n) for name, n, _ in outcome_bars(rate, counts.valid_failures)] == [
        ("success", 3),
        ("timeout", 2),
        ("failed", 4),
    ]
    text = failures_text(counts)
    assert "n = 2 timeouts, 4 failed" in text
    assert draw_outcomes(rate, counts.valid_failures).startswith(PNG)


def test_without_failed_trials_the_figures_say_what_they_said(tmp_path: Path) -> None:
    result = _audit(tmp_path / "s.sqlite", ["success"] * 3 + ["timeout"] * 2)
    counts = DispositionCounts.of(result.trials)
    rate = SuccessRate.of(result.trials)
    assert [(name, n) for name, n, _ in outcome_bars(rate)] == [("success", 3), ("timeout", 2)]
    assert failures_text(counts) == (
        "Timeouts, kept as valid failures\nn = 2\n0 flagged, kept and marked"
    )

"""Success rate with its Wilson interval (the paper's 37/53) and grouped statistics."""

from __future__ import annotations

import html
import json
from pathlib import Path

import pytest

from tests.audit import synthetic
from tests.audit.builders import write_trial
from workcell.audit.run import AuditResult, run_audit
from workcell.audit.stats import grouped
from workcell.audit.store_source import StoreSource
from workcell.audit.write import write_outputs
from workcell.record import Store


def _audit(path: Path) -> AuditResult:
    source = StoreSource(path)
    try:
        return run_audit(source)
    finally:
        source.close()


def test_the_papers_37_of_53_interval_appears_in_summary_and_report(tmp_path: Path) -> None:
    store = tmp_path / "paper.sqlite"
    outcomes = ["success"] * 37 + ["timeout"] * 16 + ["interrupted"] * 3
    synthetic.fill(store, outcomes, n_frames=30)
    result = _audit(store)
    paths = write_outputs(result, tmp_path / "out")
    summary = json.loads(paths["summary.json"].read_text())
    rate = summary["success_rate"]
    assert (rate["successes"], rate["n"]) == (37, 53)
    assert round(100 * rate["rate"], 2) == 69.81
    assert (round(100 * rate["low"], 2), round(100 * rate["high"], 2)) == (56.46, 80.48)
    assert summary["counts"]["raw"] == 56 and summary["counts"]["incomplete"] == 3
    assert summary["metrics"]["completion_time_s"]["n"] == 37
    report = html.unescape(paths["report.html"].read_text())
    assert "69.81 % [56.46, 80.48]" in report


def test_groups_appear_where_there_is_more_than_one_value(tmp_path: Path) -> None:
    path = tmp_path / "two.sqlite"
    with Store.open(path, writer=True) as store:
        for k, (operator, outcomes) in enumerate((("ana", "sst"), ("ben", "stt"))):
            session_id = store.create_session(synthetic.session_info(operator_id=operator))
            for i, code in enumerate(outcomes):
                outcome = "success" if code == "s" else "timeout"
                write_trial(store, session_id, synthetic.frames(30, 10 * k + i), outcome)
            store.end_session(session_id)
    groups = grouped(_audit(path).trials)
    assert set(groups) == {"session", "operator"}
    rates = [(g.value, g.rate.successes, g.rate.n) for g in groups["operator"]]
    assert rates == [("ana", 2, 3), ("ben", 1, 3)]
    assert groups["operator"][0].metrics["completion_time_s"].n == 2
    assert groups["operator"][1].rate.low == pytest.approx(0.0615, abs=1e-4)

"""The cross-check reproduces every stored metric and names each one that was tampered."""

from __future__ import annotations

import math
import sqlite3
from pathlib import Path

from tests.audit import builders as b
from tests.audit.conftest import ExpertStores
from workcell.audit.crosscheck import Tolerance
from workcell.audit.findings import METRIC_MISMATCH
from workcell.audit.run import AuditResult, run_audit
from workcell.audit.store_source import StoreSource
from workcell.record import Store


def test_tolerance() -> None:
    tol = Tolerance()
    assert tol.agree(None, math.nan)
    assert not tol.agree(None, 0.0)
    assert tol.agree(2.0, 2.0 * (1 + 5e-10))
    assert not tol.agree(2.0, 2.0 * (1 + 5e-9))
    assert tol.agree(0.0, 1e-13)
    assert tol.agree(math.inf, math.inf) and not tol.agree(math.inf, 1e300)


def test_an_honest_store_reproduces_every_stored_metric(scenario_audit: AuditResult) -> None:
    assert all(t.mismatches == () for t in scenario_audit.trials)
    assert not [f for f in scenario_audit.findings if f.kind == METRIC_MISMATCH]


def test_tampered_stored_metrics_are_findings(expert_stores: ExpertStores, tmp_path: Path) -> None:
    path = tmp_path / "tampered.sqlite"
    with Store.open(expert_stores.skilled, writer=False) as source:
        session = source.sessions()[0]
        frames = [b.columns(source, t.trial_id) for t in source.trials()[:3]]
    with Store.open(path, writer=True) as store:
        session_id = store.create_session(b.session_info(session))
        ids = [b.write_trial(store, session_id, f, "success") for f in frames]
        store.end_session(session_id)
    conn = sqlite3.connect(path)
    conn.execute(
        "UPDATE trials SET path_length_m = path_length_m * 1.001 WHERE trial_id = ?", (ids[0],)
    )
    conn.execute(
        "UPDATE trials SET smoothness = smoothness * (1 + 1e-7), n_frames = n_frames - 1 "
        "WHERE trial_id = ?",
        (ids[2],),
    )
    conn.commit()
    conn.close()
    source_ = StoreSource(path)
    try:
        result = run_audit(source_)
    finally:
        source_.close()
    found = [(f.trial_id, f.subject) for f in result.findings if f.kind == METRIC_MISMATCH]
    assert found == [(ids[0], "path_length_m"), (ids[2], "n_frames"), (ids[2], "smoothness")]
    message = next(f.message for f in result.findings if f.trial_id == ids[0])
    assert message.startswith("path_length_m: stored ")
    # a mismatch is a finding, not a verdict: the trial keeps its disposition
    assert all(t.disposition.included for t in result.trials)

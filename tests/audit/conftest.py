"""Shared audit fixtures: real expert trials (``workcell collect`` run once per test
session, two sessions in parallel) and a constructed store covering every disposition."""

from __future__ import annotations

import os
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import pytest

from tests.audit import builders as b
from workcell.audit.run import AuditResult, run_audit
from workcell.audit.store_source import StoreSource
from workcell.record import SessionRecord, Store

EXPERT_TRIALS = 4
SLOW_TRIALS = 2
OSCILLATION = {"frequency_hz": 3.0, "amplitude_rad": 0.03, "start_s": 2.0, "duration_s": 3.0}


@dataclass(frozen=True)
class ExpertStores:
    """``skilled``: successes of the expert at skill 1; ``slow``: timeouts at skill 0.3."""

    skilled: Path
    slow: Path


def _collect(path: Path, *extra: str) -> subprocess.Popen[str]:
    argv = [sys.executable, "-m", "workcell", "collect", "--mode", "collection", "--store"]
    env = {**os.environ, "MUJOCO_GL": os.environ.get("MUJOCO_GL", "egl")}
    return subprocess.Popen(
        [*argv, str(path), *extra],
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
        env=env,
    )


@pytest.fixture(scope="session")
def expert_stores(tmp_path_factory: pytest.TempPathFactory) -> ExpertStores:
    folder = tmp_path_factory.mktemp("expert")
    stores = ExpertStores(folder / "skilled.sqlite", folder / "slow.sqlite")
    runs = [
        _collect(stores.skilled, "--trials", str(EXPERT_TRIALS), "--seed", "3"),
        _collect(
            stores.slow,
            *("--trials", str(SLOW_TRIALS), "--seed", "4", "--skill", "0.3"),
            *("--set", "task.time_limit_s=20", "--operator-id", "novice"),
        ),
    ]
    for run in runs:
        out, _ = run.communicate(timeout=300)
        assert run.returncode == 0, out
    return stores


@dataclass(frozen=True)
class Scenario:
    """A store with one trial per case of Fig. 4; ``ids`` by case name."""

    path: Path
    ids: dict[str, str]


def expert_trials(
    stores: ExpertStores,
) -> tuple[SessionRecord, list[b.Columns], list[b.Columns]]:
    """The skilled store's session, its trials' frames (successes) and the slow store's
    (timeouts), as :func:`builders.columns` gives them."""
    with (
        Store.open(stores.skilled, writer=False) as skilled,
        Store.open(stores.slow, writer=False) as slow,
    ):
        wins = [b.columns(skilled, t.trial_id) for t in skilled.trials()]
        losses = [b.columns(slow, t.trial_id) for t in slow.trials()]
        return skilled.sessions()[0], wins, losses


@pytest.fixture(scope="session")
def scenario(expert_stores: ExpertStores, tmp_path_factory: pytest.TempPathFactory) -> Scenario:
    path = tmp_path_factory.mktemp("scenario") / "scenario.sqlite"
    session, wins, losses = expert_trials(expert_stores)
    assert len(wins) == EXPERT_TRIALS and len(losses) == SLOW_TRIALS
    cases = {
        "clean": (wins[0], "success", None),
        "reviewer_excluded": (wins[1], "success", None),
        "oscillating": (b.with_oscillation(wins[2], "arm_r_4", **OSCILLATION), "success", None),
        "reviewer_included": (
            b.with_oscillation(wins[3], "arm_l_2", **OSCILLATION),
            "success",
            None,
        ),
        "oscillating_timeout": (
            b.with_oscillation(losses[0], "arm_r_6", **OSCILLATION),
            "timeout",
            None,
        ),
        "timeout": (losses[1], "timeout", None),
        "quit": (b.truncated(wins[0], 200), "interrupted", "application_quit"),
        "crashed": (b.truncated(wins[1], 120), "interrupted", "crash_recovered"),
        "gap": (b.with_gap(wins[1], 150, 1.0), "success", None),
    }
    ids: dict[str, str] = {}
    with Store.open(path, writer=True) as store:
        session_id = store.create_session(b.session_info(session))
        for name, (frames, outcome, reason) in cases.items():
            ids[name] = b.write_trial(
                store, session_id, frames, outcome, interruption_reason=reason
            )
        store.end_session(session_id)
        store.annotate(ids["reviewer_excluded"], "exclude", "operator was distracted", "ana")
        store.annotate(ids["reviewer_included"], "exclude", "first look", "ana")
        store.annotate(ids["reviewer_included"], "include", "wobble is the conveyor's", "ben")
        store.annotate(ids["crashed"], "include", "looks fine", "ben")
        store.annotate(ids["clean"], "note", "nice run", "ana")
    return Scenario(path, ids)


@pytest.fixture(scope="session")
def scenario_audit(scenario: Scenario) -> AuditResult:
    source = StoreSource(scenario.path)
    try:
        return run_audit(source)
    finally:
        source.close()

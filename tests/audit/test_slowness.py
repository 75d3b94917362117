"""The ``slow`` detector: a success far slower than the audited set's typical success of the
same task is marked (or excluded, when configured so), and left out of ``--audited``
exports; what it does not touch stays as it was."""

from __future__ import annotations

import csv
import statistics
from pathlib import Path

import pytest

from tests.audit import builders as b
from tests.audit.conftest import ExpertStores, expert_trials
from workcell.audit.config import AuditConfig
from workcell.audit.disposition import EXCLUDED_LOW_QUALITY, VALID_SUCCESS, VALID_TIMEOUT
from workcell.audit.findings import QUALITY_FLAG
from workcell.audit.flags import SLOW
from workcell.audit.population import flag_slow
from workcell.audit.run import AuditResult, run_audit
from workcell.audit.slowness import SlownessParams, detect_slow
from workcell.audit.store_source import StoreSource
from workcell.cli.main import main
from workcell.errors import ConfigError
from workcell.export.audited import audited_inclusions
from workcell.record import Store

PAUSE_S = 40.0


@pytest.fixture(scope="module")
def hesitant(expert_stores: ExpertStores, tmp_path_factory: pytest.TempPathFactory) -> Path:
    """Four real expert successes, one copy of the first that stands still for 40 s half-way
    (a hesitation), and two real timeouts."""
    path = tmp_path_factory.mktemp("slowness") / "hesitant.sqlite"
    session, wins, losses = expert_trials(expert_stores)
    middle = len(wins[0]["t_sim"]) // 2
    with Store.open(path, writer=True) as store:
        session_id = store.create_session(b.session_info(session))
        for frames in wins:
            b.write_trial(store, session_id, frames, "success")
        b.write_trial(store, session_id, b.with_pause(wins[0], middle, PAUSE_S), "success")
        for frames in losses:
            b.write_trial(store, session_id, frames, "timeout")
        store.end_session(session_id)
    return path


@pytest.fixture(scope="module")
def corrected(expert_stores: ExpertStores, tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The hesitant set, but a person took over in the paused trial (a corrected rollout),
    and three successes of another task, each as slow as the pause (a longer task)."""
    path = tmp_path_factory.mktemp("slowness") / "corrected.sqlite"
    session, wins, _ = expert_trials(expert_stores)
    middle = len(wins[0]["t_sim"]) // 2
    paused = b.with_pause(wins[0], middle, PAUSE_S)
    with Store.open(path, writer=True) as store:
        session_id = store.create_session(b.session_info(session))
        for frames in wins:
            b.write_trial(store, session_id, frames, "success")
        b.write_trial(store, session_id, paused, "success", take_overs=(5.0,))
        for _ in range(3):
            b.write_trial(store, session_id, paused, "success", task="sort")
        store.end_session(session_id)
    return path


def _audit(path: Path, config: AuditConfig | None = None) -> AuditResult:
    source = StoreSource(path)
    try:
        return run_audit(source, config)
    finally:
        source.close()


def test_a_hesitation_is_marked_slow_against_the_sets_median(hesitant: Path) -> None:
    result = _audit(hesitant)
    *fast, paused = [t for t in result.trials if t.row.outcome == "success"]
    times = [t.metrics.completion_time_s for t in (*fast, paused)]
    assert all(t is not None for t in times)
    median = statistics.median(t for t in times if t is not None)
    assert paused.metrics.completion_time_s is not None
    assert paused.metrics.completion_time_s > 2 * median  # the pause makes it slow
    assert [f.name for f in paused.flags] == [SLOW]
    (flag,) = paused.flags
    ratio = paused.metrics.completion_time_s / median
    assert f"{ratio:.1f}x the median {median:.1f} s of 5 valid successes" in flag.detail
    assert not flag.disqualifying
    assert paused.disposition.stage == VALID_SUCCESS and paused.disposition.marked
    assert all(t.flags == () and not t.disposition.marked for t in fast)
    timeouts = [t for t in result.trials if t.row.outcome == "timeout"]
    assert len(timeouts) == 2
    assert all(t.disposition.stage == VALID_TIMEOUT and SLOW not in {f.name for f in t.flags}
               for t in timeouts)  # fmt: skip
    slow_findings = [f for f in result.findings if f.kind == QUALITY_FLAG and f.subject == SLOW]
    assert [f.trial_id for f in slow_findings] == [paused.trial_id]
    assert result.config.describe()["detectors"]["slow"]["factor"] == 1.5


def test_the_audited_export_leaves_the_slow_demonstration_out(hesitant: Path) -> None:
    decisions = audited_inclusions(hesitant)
    left_out = {i: d.reason for i, d in decisions.items() if not d.included}
    paused = next(t for t in _audit(hesitant).trials if t.flags)
    assert left_out == {paused.trial_id: "marked by a quality flag: slow"}


def test_a_corrected_trial_and_another_tasks_are_not_measured_against_these(
    corrected: Path,
) -> None:
    result = _audit(corrected)
    assert all(t.flags == () for t in result.trials)  # as slow as the pause, none flagged
    tasks = [t.task for t in result.trials]
    assert tasks == ["box_transfer"] * 5 + ["sort"] * 3
    assert audited_inclusions(corrected).keys() == {t.trial_id for t in result.trials}
    assert all(d.included for d in audited_inclusions(corrected).values())
    # without its take-over the same trial is slow against the four others (its own
    # reference, as before), and the slow other task against nothing of box transfer's
    flagged = flag_slow(result.trials, SlownessParams())
    assert [bool(t.flags) for t in flagged] == [False] * 4 + [True] + [False] * 3
    assert result.config.describe()["detectors"]["slow"]["version"] == "3"


def test_slow_can_disqualify_and_needs_a_reference(hesitant: Path) -> None:
    strict = _audit(hesitant, AuditConfig(slowness=SlownessParams(disqualifying=True)))
    stages = [t.disposition.stage for t in strict.trials if t.row.outcome == "success"]
    assert stages == [VALID_SUCCESS] * 4 + [EXCLUDED_LOW_QUALITY]
    assert strict.trials[4].disposition.exclusion_reason == "low quality: slow"
    too_few = _audit(hesitant, AuditConfig(slowness=SlownessParams(min_reference=6)))
    assert all(t.flags == () for t in too_few.trials)
    lenient = _audit(hesitant, AuditConfig(slowness=SlownessParams(factor=4.0)))
    assert all(t.flags == () for t in lenient.trials)


def test_detect_slow_by_hand() -> None:
    params = SlownessParams(factor=2.0)
    assert detect_slow(40.0, 20.0, 7, params) is None  # exactly 2x is not beyond it
    flag = detect_slow(50.0, 20.0, 7, params)
    assert flag is not None and flag.name == SLOW
    assert flag.detail == (
        "completed in 50.0 s, 2.5x the median 20.0 s of 7 valid successes of this task (limit 2x)"
    )
    assert detect_slow(None, 20.0, 7, params) is None


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"factor": 0.5}, "slowness.factor = 0.5: must be between 1 and 100"),
        ({"factor": float("nan")}, "slowness.factor = nan: must be between 1 and 100"),
        (
            {"min_reference": 0},
            "slowness.min_reference = 0: must be a whole number from 1 to 1000000 trials",
        ),
    ],
)
def test_bad_slowness_parameters_are_named(kwargs: dict[str, float], message: str) -> None:
    with pytest.raises(ConfigError, match=message):
        SlownessParams(**kwargs)  # type: ignore[arg-type]


def test_workcell_audit_prints_how_many_trials_a_flag_marks(
    hesitant: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "report"
    assert main(["audit", "--store", str(hesitant), "--out", str(out), "--workers", "1"]) == 0
    first = capsys.readouterr().out.splitlines()[0]
    assert "7 valid (5 successes, 2 timeouts)" in first
    assert "0 low quality, 0 excluded by reviewer, 1 marked by a quality flag;" in first
    with (out / "trials.csv").open() as file:
        rows = list(csv.DictReader(file))
    assert [row["flag_slow"] for row in rows] == ["0"] * 4 + ["1"] + ["0"] * 2

"""``workcell evaluate`` end to end with the expert: real MuJoCo, a real store, the audit's
ladder read back from it."""

from __future__ import annotations

import base64
import contextlib
import io
import json
import re
import signal
import sqlite3
import statistics
import subprocess
import sys
from pathlib import Path

import pytest

from workcell.cli.main import main
from workcell.record.verify import verify_store
from workcell.task.runner import trial_seed

SEED = 1000
ROLLOUTS = 2
PNG = b"\x89PNG\r\n\x1a\n"
ROLLOUTS_STOPPED = 50
"""Rollouts asked of the run stopped by SIGINT after its first: more than ever end first."""


def _evaluate(capsys: pytest.CaptureFixture[str], *args: str) -> tuple[int, str, str]:
    status = main(["evaluate", "--policy", "expert", "--seed", str(SEED), *args])
    out, err = capsys.readouterr()
    return status, out, err


def _trials(store: Path) -> list[tuple[str, str, int, str, float | None, str]]:
    """(operator, world, trial seed, outcome, completion time, stage) of every trial."""
    with sqlite3.connect(store) as db:
        return list(
            db.execute(
                "SELECT operator_id, world, trial_seed, outcome, completion_time_s, stage "
                "FROM trials JOIN sessions USING (session_id) ORDER BY world, trial_seed"
            )
        )


@pytest.fixture(scope="module")
def two_worlds(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, str, str]:
    """The expert evaluated in D0 and D1, 2 rollouts each: the store, stdout, stderr."""
    return _run(tmp_path_factory.mktemp("evaluate") / "eval.sqlite", "--world", "D0,D1")


@pytest.fixture(scope="module")
def again_in_d1(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, str, str]:
    """The expert evaluated again, in D1 alone, its rollouts split over two workers."""
    store = tmp_path_factory.mktemp("evaluate") / "again.sqlite"
    return _run(store, "--world", "D1", "--workers", "2")


def _run(store: Path, *args: str) -> tuple[Path, str, str]:
    """``evaluate`` of the expert, 2 rollouts per world (capsys is per test: by hand)."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        status = main(
            ["evaluate", "--policy", "expert", "--rollouts", str(ROLLOUTS), "--seed", str(SEED),
             "--store", str(store), *args]
        )  # fmt: skip
    assert status == 0, err.getvalue()
    return store, out.getvalue(), err.getvalue()


def test_the_table_is_the_ladder_of_what_was_recorded(two_worlds: tuple[Path, str, str]) -> None:
    store, out, err = two_worlds
    lines = out.splitlines()
    assert lines[0] == f"expert on box_transfer, seed {SEED}: {ROLLOUTS} rollouts per world"
    assert re.split(r"\s{2,}", lines[1]) == [
        "world", "successes", "success rate [Wilson 95 %]", "median time (s)", "stage reached"
    ]  # fmt: skip
    trials = _trials(store)
    for row, world in zip(lines[2:4], ("D0", "D1"), strict=True):
        times = [t[4] for t in trials if t[1] == world and t[3] == "success" and t[4]]
        assert len(times) == ROLLOUTS  # the expert delivers in every world
        assert re.split(r"\s{2,}", row) == [
            world, "2/2", "100.0 % [34.2, 100.0]", f"{statistics.median(times):.2f}", "2 delivered"
        ]  # fmt: skip
    assert lines[4] == f"recorded 2 sessions into {store}" and len(lines) == 5
    # progress on standard error while it ran: one line per rollout
    assert err.count(" rollout ") == 2 * ROLLOUTS
    assert f"  D1 rollout 2/{ROLLOUTS}: success, stage delivered" in err


def test_the_rollouts_are_stored_with_their_worlds_and_shared_seeds(
    two_worlds: tuple[Path, str, str], again_in_d1: tuple[Path, str, str]
) -> None:
    store, _, _ = two_worlds
    assert verify_store(store) == []
    trials = _trials(store)
    seeds = sorted(trial_seed(SEED, i) for i in range(ROLLOUTS))
    assert [(t[0], t[1]) for t in trials] == [("expert", "D0")] * 2 + [("expert", "D1")] * 2
    assert [t[2] for t in trials] == seeds + seeds  # the same seeds in every world
    # another run (split over two workers) meets the same worlds: same seeds, same trials
    again, out, _ = again_in_d1
    assert verify_store(again) == []
    assert _trials(again) == [t for t in trials if t[1] == "D1"]
    assert "recorded 2 sessions" in out  # one per worker


def test_the_audit_draws_the_same_ladder(
    two_worlds: tuple[Path, str, str], tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    store, out, _ = two_worlds
    report = tmp_path / "audit"
    assert main(["audit", "--store", str(store), "--out", str(report)]) == 0
    capsys.readouterr()
    summary = json.loads((report / "summary.json").read_text())
    rungs = summary["ladder"]["rungs"]
    assert [(r["operator"], r["world"], r["successes"], r["rollouts"]) for r in rungs] == [
        ("expert", "D0", 2, 2),
        ("expert", "D1", 2, 2),
    ]
    for rung in rungs:  # the numbers evaluate printed
        assert f"{100 * rung['low']:.1f}, {100 * rung['high']:.1f}]" in out
        assert f"  {rung['median_completion_s']:.2f}  " in out
        assert rung["stages"]["delivered"] == 2 and sum(rung["stages"].values()) == 2
    html = (report / "report.html").read_text()
    assert "<h3>Across worlds</h3>" in html
    figure = re.search(r'<figure id="ladder"><img src="data:image/png;base64,([^"]+)"', html)
    assert figure is not None and base64.b64decode(figure[1]).startswith(PNG)
    assert "<td>expert</td><td>box_transfer</td><td>D1</td><td>2/2</td>" in html
    # the same ladder from the store's CSV export
    exported, from_csv = tmp_path / "csv", tmp_path / "audit-csv"
    assert main(["export", "--format", "csv", "--store", str(store), "--out", str(exported)]) == 0
    assert main(["audit", "--csv", str(exported), "--out", str(from_csv)]) == 0
    capsys.readouterr()
    assert json.loads((from_csv / "summary.json").read_text())["ladder"] == summary["ladder"]


def test_one_world_draws_no_ladder(
    again_in_d1: tuple[Path, str, str], tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """The audit's outputs are unchanged for a store without several worlds."""
    report = tmp_path / "audit"
    assert main(["audit", "--store", str(again_in_d1[0]), "--out", str(report)]) == 0
    capsys.readouterr()
    assert "ladder" not in json.loads((report / "summary.json").read_text())
    html = (report / "report.html").read_text()
    assert "Across worlds" not in html and 'id="ladder"' not in html


@pytest.mark.parametrize(
    ("args", "error"),
    [
        (
            ["--world", "D0,D3"],
            "--world 'D0,D3': unknown world 'D3'; give a comma-separated list of D0, D1, D2 "
            "(e.g. D0,D1,D2)",
        ),
        (
            ["--world", "D1,D1"],
            "--world 'D1,D1': D1 is named twice; give a comma-separated list of D0, D1, D2 "
            "(e.g. D0,D1,D2)",
        ),
        (["--rollouts", "0"], "--rollouts = 0: must be a whole number from 1 to 100000 per world"),
        (
            ["--set", "world.randomization.target_shift=0.1"],
            "--set world.randomization.target_shift: evaluate sets every world.randomization "
            "range from --world; drop it (a world of your own: workcell collect --set ...)",
        ),
    ],
)
def test_bad_input_is_one_clear_error(
    args: list[str], error: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    store = tmp_path / "never.sqlite"
    arguments = ["--rollouts", "2", "--store", str(store), *args]
    status, out, err = _evaluate(capsys, *arguments)
    assert status == 2 and out == ""
    assert err == f"workcell: error: {error}\n"
    assert not store.exists()


def test_a_missing_policy_is_one_clear_error(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    store, missing = tmp_path / "never.sqlite", tmp_path / "no-such-policy"
    status = main(
        ["evaluate", "--policy", str(missing), "--rollouts", "1", "--seed", "1",
         "--store", str(store)]
    )  # fmt: skip
    out, err = capsys.readouterr()
    assert status == 2 and out == ""
    assert err.startswith(f"workcell: error: policy '{missing}': no LeRobot pretrained model")
    assert err.endswith("; or --policy expert for the scripted expert\n")
    assert err.count("\n") == 1 and not store.exists()


def test_sigint_ends_the_running_rollout_and_prints_what_was_recorded(tmp_path: Path) -> None:
    store = tmp_path / "stopped.sqlite"
    process = subprocess.Popen(
        [sys.executable, "-m", "workcell", "evaluate", "--policy", "expert", "--world", "D1",
         "--rollouts", str(ROLLOUTS_STOPPED), "--seed", str(SEED), "--store", str(store)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )  # fmt: skip
    assert process.stderr is not None
    for line in process.stderr:  # the first rollout has ended: the next is under way
        if " rollout " in line:
            break
    process.send_signal(signal.SIGINT)
    out, _ = process.communicate(timeout=120)
    assert process.returncode == 130
    assert verify_store(store) == []
    outcomes = [t[3] for t in _trials(store)]
    done, stopped = outcomes.count("success"), outcomes.count("interrupted")
    assert 1 <= done < ROLLOUTS_STOPPED and stopped <= 1 and done + stopped == len(outcomes)
    lines = out.splitlines()
    assert re.split(r"\s{2,}", lines[2])[:2] == ["D1", f"{done}/{done}"]
    assert lines[2].endswith(f"{done} delivered" + " (1 interrupted, not counted)" * stopped)
    assert lines[-1] == "stopped by SIGINT: the table counts the rollouts that ran"

"""``workcell collect`` and ``workcell config`` end to end."""

from __future__ import annotations

import json
import os
import re
import signal
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

from tests.record.processes import collect, wait_for_trials
from workcell.cli.main import main
from workcell.record import Store
from workcell.record.verify import verify_store
from workcell.session.config import SessionConfig
from workcell.session.load import resolve_session_config

JSON_KEYS = {
    "trial_index",
    "mode",
    "round",
    "level",
    "required_boxes",
    "time_limit_s",
    "outcome",
    "interruption_reason",
    "boxes_delivered",
    "score",
    "elapsed_s",
}


def test_collection_json_lines(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    store = tmp_path / "s.sqlite"
    args = ["collect", "--mode", "collection", "--trials", "2", "--json", "--store", str(store)]
    assert main(args) == 0
    lines = capsys.readouterr().out.strip().splitlines()
    rows = [json.loads(line) for line in lines]
    assert len(rows) == 2
    assert all(set(row) == JSON_KEYS for row in rows)
    assert [row["trial_index"] for row in rows] == [0, 1]
    assert all(row["outcome"] == "success" and row["mode"] == "collection" for row in rows)
    assert all(row["round"] is None and row["level"] is None for row in rows)
    assert all(row["score"] == 100 + -int(-(120 - row["elapsed_s"]) // 1) for row in rows)


def test_challenge_capped_by_trials_ends_incomplete(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["collect", "--mode", "challenge", "--trials", "2", "--no-store"]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out[0].split() == [
        "index",
        "mode",
        "round",
        "level",
        "outcome",
        "boxes",
        "score",
        "elapsed",
    ]
    assert len(out) == 4  # header, two trials, summary
    assert out[1].split()[:5] == ["0", "challenge", "1", "1", "success"]
    assert out[2].split()[:5] == ["1", "challenge", "1", "2", "success"]
    assert out[3].startswith("campaign incomplete (stopped by --trials) at round 1 level 2")


def test_bad_input_fails_before_running_one_line_per_problem(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    config = tmp_path / "bad.toml"
    config.write_text(
        "[task]\nrounds = 0\nlevel_boxes = [1, 2]\n[recording]\nsampling_rate_hz = 0\n"
    )
    code = main(["collect", "--config", str(config), "--skill", "3", "--set", "task.mdoe=1"])
    assert code == 2
    captured = capsys.readouterr()
    assert captured.out == ""  # nothing ran
    errors = captured.err.strip().splitlines()
    assert all(line.startswith("workcell: error: ") for line in errors)
    named = sorted(
        line.removeprefix("workcell: error: ").split(" ")[0].rstrip(":") for line in errors
    )
    assert named == [
        "--skill",
        "recording.sampling_rate_hz",
        "task.level_time_limits_s",
        "task.mdoe",
        "task.rounds",
    ]


def test_config_defaults_is_a_loadable_complete_file(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(["config", "--defaults"]) == 0
    text = capsys.readouterr().out
    path = tmp_path / "defaults.toml"
    path.write_text(text)
    assert tomllib.loads(text)["task"]["level_boxes"] == [1, 2, 3]
    assert resolve_session_config(path) == SessionConfig()
    assert main(["config", "--config", str(path), "--set", "task.rounds=2"]) == 0
    assert "rounds = 2" in capsys.readouterr().out


def _column_ends(line: str) -> list[int]:
    """Where each right-aligned cell of a table line ends."""
    return [
        i + 1 for i, c in enumerate(line) if c != " " and (i + 1 == len(line) or line[i + 1] == " ")
    ]


@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGTERM])
def test_a_signal_ends_the_running_trial_as_application_quit(
    tmp_path: Path, signum: signal.Signals
) -> None:
    env = {**os.environ, "PYTHONUNBUFFERED": "1"}
    process = subprocess.Popen(
        [
            *(sys.executable, "-m", "workcell", "collect", "--mode", "collection"),
            *("--store", str(tmp_path / "s.sqlite")),
        ],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env=env,
    )
    assert process.stdout is not None
    header = process.stdout.readline().rstrip("\n")
    first = process.stdout.readline().rstrip("\n")  # one trial finished: the next runs
    assert first.split()[4] == "success"
    # past the next trial's countdown (a trial stopped in its countdown never started)
    wait_for_trials(tmp_path / "s.sqlite", 2)
    process.send_signal(signum)
    out, err = process.communicate(timeout=60)
    assert process.returncode == 128 + signum  # 130 for SIGINT, 143 for SIGTERM
    last = out.splitlines()[0]
    assert last.split()[:5] == ["1", "collection", "-", "-", "interrupted:application_quit"]
    # the longest outcome label keeps the table aligned under its header
    assert len(header) == len(first) == len(last)
    assert _column_ends(header) == _column_ends(first) == _column_ends(last)
    assert "Traceback" not in err


@pytest.mark.parametrize("end", ["closed output", "SIGINT"])
def test_what_collect_prints_is_what_the_store_holds_when_it_ends_in_a_countdown(
    tmp_path: Path, end: str
) -> None:
    """``collect --json | head -n 1``, or Ctrl-C, during the next trial's countdown: that
    trial never started, so the store holds no row of it, and neither the printed rows nor
    the summary count it (the summary said 2 trials where the store held 1)."""
    store = tmp_path / "s.sqlite"
    countdown = ("--set", "task.countdown_s=30")
    process = collect(store, "--mode", "collection", "--trials", "3", *countdown)
    assert process.stdout is not None and process.stderr is not None
    printed = [json.loads(process.stdout.readline())]  # the first trial ended: 30 s countdown
    if end == "SIGINT":
        process.send_signal(signal.SIGINT)
        printed += [json.loads(line) for line in process.stdout.read().splitlines()]
        expected = 128 + signal.SIGINT
    else:
        process.stdout.close()
        expected = 128 + signal.SIGPIPE
    err = process.stderr.read()
    process.wait(timeout=120)
    assert process.returncode == expected, err
    assert "Traceback" not in err
    with Store.open(store, writer=False) as reader:
        (session,) = reader.sessions()
        trials = reader.trials()
        frames = reader.counts().frames
    assert session.status == "interrupted"
    assert [t.outcome for t in trials] == [p["outcome"] for p in printed] == ["success"]
    score = printed[0]["score"]
    assert f"1 trials, 1 succeeded, total score {score}" in err.splitlines()
    assert f"recorded session {session.session_id} ({frames} frames) in {store}" in err


def test_workers_whose_output_closes_end_like_sigint_and_merge_what_they_recorded(
    tmp_path: Path,
) -> None:
    """``collect --workers 2 --json | head -n 1``: no traceback, every worker ends its
    trial as on SIGINT, the shards are merged into a store that verifies, and the summary
    counts what the store holds; exit 141 (the run left its shards unmerged and workers
    running)."""
    store = tmp_path / "s.sqlite"
    process = collect(store, "--mode", "collection", "--trials", "6", "--workers", "2")
    assert process.stdout is not None and process.stderr is not None
    first = json.loads(process.stdout.readline())
    process.stdout.close()
    err = process.stderr.read()
    process.wait(timeout=300)
    assert process.returncode == 128 + signal.SIGPIPE, err
    assert "Traceback" not in err and "BrokenPipe" not in err, err
    assert first["outcome"] == "success"
    assert verify_store(store) == []
    with Store.open(store, writer=False) as reader:
        sessions = reader.sessions()
        trials = reader.trials()
    assert [s.status for s in sessions] == ["interrupted", "interrupted"]
    merged = r"^(\d+) trials, \d+ succeeded; merged 2 shards .*: 2 sessions, (\d+) trials"
    summary = re.search(merged, err, re.MULTILINE)
    assert summary is not None, err
    assert int(summary[1]) == int(summary[2]) == len(trials)
    assert not (tmp_path / "s.sqlite.shards").exists()

"""Worker processes write shards; merge combines them, recovers crashed ones, refuses
incompatible ones. Real processes, real SQLite."""

from __future__ import annotations

import hashlib
import json
import os
import pickle
import shutil
import signal
import sqlite3
import subprocess
import sys
import time
from pathlib import Path

import pytest

from workcell.cli.main import main
from workcell.export.camera_sources import recorded_videos
from workcell.export.lerobot_export import export_lerobot
from workcell.export.options import ExportOptions
from workcell.record import Store, StoreError
from workcell.record.merge import MergeError, merge_stores
from workcell.record.schema import SCHEMA_VERSION
from workcell.record.verify import verify_store
from workcell.scale.plan import plan_workers
from workcell.scale.worker import WorkerJob, collect_shard
from workcell.session.config import SessionConfig, TaskConfig
from workcell.task.runner import TrialResult


def collect(store: Path, *args: str) -> None:
    code = main(["collect", "--mode", "collection", "--store", str(store), "--json", *args])
    assert code == 0


def audit(store: Path, out: Path) -> dict[str, object]:
    """Audit the store; the summary's disposition counts."""
    assert main(["audit", "--store", str(store), "--out", str(out)]) == 0
    summary = json.loads((out / "summary.json").read_text())
    assert (out / "report.html").stat().st_size > 10_000
    counts = summary["counts"]
    assert isinstance(counts, dict)
    return counts


def test_plan_splits_trials_and_seeds() -> None:
    plans = plan_workers(3, 7, 10, Path("shards"))
    assert [p.trials for p in plans] == [4, 3, 3]
    assert len({p.seed for p in plans}) == 3
    assert plans == plan_workers(3, 7, 10, Path("shards"))  # reproducible
    assert [p.trials for p in plan_workers(4, 0, 2, Path("s"))] == [1, 1]


def test_a_worker_takes_a_pickled_job_and_hands_back_each_trials_result(
    tmp_path: Path,
) -> None:
    config = SessionConfig(seed=5, operator_id="expert", task=TaskConfig(mode="collection"))
    job = WorkerJob(config=config, shard=tmp_path / "shard.sqlite", trials=2)
    job = pickle.loads(pickle.dumps(job))  # what a worker process or a Ray task receives
    results: list[TrialResult] = []
    assert collect_shard(job, results.append) == 0
    assert [(r.spec.trial_index, r.outcome) for r in results] == [(0, "success"), (1, "success")]
    assert verify_store(job.shard) == []
    with Store.open(job.shard, writer=False) as reader:
        (session,) = reader.sessions()
        assert [t.score for t in reader.trials()] == [r.score for r in results]
    assert (session.seed, session.operator_id) == (5, "expert")


@pytest.mark.slow
def test_two_workers_merge_into_a_store_that_verifies(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    store = tmp_path / "merged.sqlite"
    collect(store, "--trials", "4", "--workers", "2")
    rows = [json.loads(line) for line in capsys.readouterr().out.splitlines()]
    assert sorted(row["worker"] for row in rows) == [0, 0, 1, 1]
    assert verify_store(store) == []
    with Store.open(store, writer=False) as reader:
        sessions = reader.sessions()
        trials = reader.trials()
    assert len(sessions) == 2 and len(trials) == 4
    assert len({s.seed for s in sessions}) == 2
    assert audit(store, tmp_path / "audit")["raw"] == 4
    assert not (tmp_path / "merged.sqlite.shards").exists()  # shards removed once merged


def test_camera_videos_of_workers_travel_with_the_merge(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    store = tmp_path / "merged.sqlite"
    collect(store, "--trials", "2", "--workers", "2", "--mode", "practice",
            "--cameras", "head_cam", "--camera-size", "32x24")  # fmt: skip
    capsys.readouterr()
    assert not (tmp_path / "merged.sqlite.shards").exists()
    with Store.open(store, writer=False) as reader:
        trials = reader.trials()
        videos = [recorded_videos(store, reader.events(t.trial_id))["head_cam"] for t in trials]
    assert len(videos) == 2
    for video, trial in zip(videos, trials, strict=True):
        assert video.path == tmp_path / "merged.sqlite.media" / trial.trial_id / "head_cam.mp4"
        assert hashlib.sha256(video.path.read_bytes()).hexdigest() == video.sha256
    out = tmp_path / "dataset"
    summary = export_lerobot(store, out, ExportOptions(cameras=("head_cam",)))
    assert (summary.recorded_videos, summary.rendered_videos) == (2, 0)
    # `workcell merge` of shards elsewhere copies them too, and leaves the shards' own
    moved = tmp_path / "elsewhere" / "again.sqlite"
    moved.parent.mkdir()
    report = merge_stores([store], moved)
    assert report.media_files == 2 and videos[0].path.is_file()
    with Store.open(moved, writer=False) as reader:
        again = recorded_videos(moved, reader.events(trials[0].trial_id))["head_cam"]
    assert again.path.parent.parent == moved.parent / "again.sqlite.media"


def test_a_crashed_shard_is_recovered_in_the_merge(tmp_path: Path) -> None:
    shard = tmp_path / "crashed.sqlite"
    process = subprocess.Popen(
        [
            *(sys.executable, "-m", "workcell", "collect", "--mode", "collection", "--json"),
            *("--store", str(shard)),
        ],
        stdout=subprocess.PIPE,
        text=True,
        env={**os.environ, "PYTHONUNBUFFERED": "1"},
    )
    assert process.stdout is not None
    json.loads(process.stdout.readline())  # one trial done, the next is running
    _wait_for_an_open_trial(shard)
    process.send_signal(signal.SIGKILL)
    process.wait(timeout=30)
    healthy = tmp_path / "healthy.sqlite"
    collect(healthy, "--trials", "1")
    out = tmp_path / "out.sqlite"
    report = merge_stores([shard, healthy], out)
    assert report.recovered_trials == 1
    assert verify_store(out) == []
    with Store.open(out, writer=False) as reader:
        reasons = [t.interruption_reason for t in reader.trials()]
    assert reasons.count("crash_recovered") == 1


def _wait_for_an_open_trial(store: Path, timeout_s: float = 120.0) -> None:
    """Until the store holds the second trial, started and without an outcome (the writer
    process commits what the simulation published a little later: the first trial's end
    too, which the printed line announced before it was written)."""
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        try:
            with sqlite3.connect(f"file:{store}?mode=ro", uri=True) as db:
                open_trials = db.execute(
                    "SELECT count(*) FROM trials WHERE outcome IS NULL AND trial_index >= 1"
                ).fetchone()[0]
        except sqlite3.Error:
            open_trials = 0
        if open_trials:
            return
        time.sleep(0.05)
    raise AssertionError(f"no trial of {store} was left open within {timeout_s} s")


def test_merge_refuses_what_cannot_be_combined(tmp_path: Path) -> None:
    shard = tmp_path / "a.sqlite"
    collect(shard, "--trials", "1")
    out = tmp_path / "out.sqlite"
    merge_stores([shard], out)
    with pytest.raises(MergeError, match="merged before"):
        merge_stores([shard], out)

    other = tmp_path / "b.sqlite"
    shutil.copy(shard, other)
    conn = sqlite3.connect(other)
    conn.execute("UPDATE sessions SET joint_order_json = '[\"spine\"]'")
    conn.commit()
    conn.close()
    fresh = tmp_path / "c.sqlite"
    collect(fresh, "--trials", "1")
    with pytest.raises(MergeError, match="joint order"):
        merge_stores([fresh, other], tmp_path / "out2.sqlite")

    newer = tmp_path / "newer.sqlite"
    shutil.copy(fresh, newer)
    conn = sqlite3.connect(newer)
    conn.execute(f"PRAGMA user_version = {SCHEMA_VERSION + 1}")
    conn.commit()
    conn.close()
    with pytest.raises(StoreError, match=f"schema version {SCHEMA_VERSION + 1}"):
        merge_stores([newer], tmp_path / "out3.sqlite")


def test_merge_cli_and_workers_bad_input(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert (
        main(["merge", "--out", str(tmp_path / "o.sqlite"), str(tmp_path / "absent.sqlite")]) == 2
    )
    assert "workcell: error:" in capsys.readouterr().err
    assert main(["collect", "--workers", "0", "--store", str(tmp_path / "x.sqlite")]) == 2
    assert "--workers = 0" in capsys.readouterr().err


@pytest.mark.slow
def test_ray_local_run_merges_into_a_store_that_verifies(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    store = tmp_path / "ray.sqlite"
    collect(store, "--trials", "2", "--workers", "2", "--ray", "local")
    rows = [json.loads(line) for line in capsys.readouterr().out.splitlines()]
    assert sorted(row["worker"] for row in rows) == [0, 1]
    assert all(row["outcome"] == "success" for row in rows)
    assert verify_store(store) == []
    with Store.open(store, writer=False) as reader:
        assert reader.counts().trials == 2
    assert audit(store, tmp_path / "audit")["raw"] == 2

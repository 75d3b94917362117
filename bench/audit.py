"""Audit throughput: recomputing every metric and detector from a store's frames.

Generates a store of synthetic trials through the Store API (no simulation), then prints,
measured in one run, in frames per second:
- plain read: ``Store.frames`` of every trial (all frame columns, as exported), the baseline;
- SQLite alone: the 41 columns the metrics need summed inside SQLite, no Python objects
  (an upper bound for any reader that goes through SQLite rows);
- the audit's read of the 41 columns from the frame rows (one SELECT per trial), and from
  the frame blocks (what it reads by default);
- recompute only: metrics + detectors + cross-check on frames already in memory;
- end to end: ``run_audit`` on the store (read + recompute + detectors + dispositions) in
  one process pinned to one core (CPU seconds, robust to a shared machine) and with one
  worker process per core (wall seconds), and its ratio to the plain read. Target:
  1,000,000 frames/s end to end. The parallel audit must conclude exactly what the
  one-process audit does.
- task stages: the extra pass that reads how far each trial without a delivery got
  (contacts, grasp and the held box's pose from the ``boxes`` JSON), and its share of the
  end-to-end time (the synthetic trials hold box 0 for 40 % of their frames).
Then the seconds to write report.html, summary.json and trials.csv. Each figure is the
best of ``--repeats`` runs.

Run: ``.venv/bin/python bench/audit.py [--trials 1000] [--frames 450] [--store PATH]``.
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np

from workcell.audit.run import run_audit
from workcell.audit.source import FRAME_COLUMNS_READ
from workcell.audit.store_source import StoreSource
from workcell.audit.trial_audit import audit_trial
from workcell.audit.write import write_outputs
from workcell.metrics import (
    METRIC_DEFINITIONS,
    METRICS_VERSION,
    FrameArrays,
    MetricThresholds,
    compute_trial_metrics,
)
from workcell.record import SessionInfo, Store, StoredMetrics, TrialEnd, TrialStart
from workcell.record.batch import frames_from_columns
from workcell.record.columns import FRAME_COLUMNS, FRAME_DEVICE_COLUMNS
from workcell.record.connection import connect
from workcell.record.schema import column_list

RATE_HZ = 20.0
THRESHOLDS = MetricThresholds()


def pin_to_one_core() -> set[int]:
    """Pin this process to one core; returns the cores it could use before."""
    cores = set(os.sched_getaffinity(0))
    os.sched_setaffinity(0, {min(cores)})
    return cores


def synthetic_frames(rng: np.random.Generator, n: int, oscillate: bool) -> dict[str, Any]:
    """One trial: smooth reaches of both arms under an active grip, a driving base, TCPs
    that follow, sensor noise; optionally a 3 Hz arm oscillation of 0.05 rad for 3 s."""
    t = np.arange(n) / RATE_HZ
    s = t / t[-1]
    cols: dict[str, Any] = {
        c: np.zeros(n)
        for c in FRAME_COLUMNS
        if c not in ("session_id", "trial_id", "boxes", "stage")
    }
    cols.pop("frame_index")
    cols["t_sim"] = t
    cols["t_wall"] = 1.76e9 + t + rng.uniform(0.0, 2e-3, n)
    bump = np.exp(-(((s - 0.6) / 0.08) ** 2))
    for side, sign in (("l", 1.0), ("r", -1.0)):
        for j in range(1, 8):
            q = 0.3 * sign * np.sin(np.pi * s * (1 + j % 3)) + 0.2 * bump + rng.normal(0, 1e-4, n)
            cols[f"q_arm_{side}_{j}"] = q
            cols[f"dq_arm_{side}_{j}"] = np.gradient(q) * RATE_HZ
        cols[f"grip_{side}"] = (s > 0.03).astype(float)
        cols[f"tcp_{side}_x"] = 3.0 * s + 0.1 * bump
        cols[f"tcp_{side}_y"] = sign * 0.25 + np.sin(2 * np.pi * s)
        cols[f"tcp_{side}_z"] = 0.9 + 0.2 * bump
    if oscillate:
        window = (t > 5.0) & (t < 8.0)
        cols["q_arm_r_4"][window] += 0.05 * np.sin(2 * np.pi * 3.0 * t[window])
    cols["base_vx"] = 0.4 * np.sin(np.pi * s)
    for c in FRAME_DEVICE_COLUMNS:
        cols[c] = np.full(n, np.nan)
    held = (s > 0.35) & (s < 0.75)  # box 0 between the grippers, from the belt to the table
    for c in ("contact_l", "contact_r", "attached"):
        cols[c] = np.where(held, 0, -1)
    for c in ("follow_l", "follow_r"):
        cols[c] = np.ones(n, dtype=np.int64)
    x = (cols["tcp_l_x"] + cols["tcp_r_x"]) / 2
    y = (cols["tcp_l_y"] + cols["tcp_r_y"]) / 2
    z = np.where(held, cols["tcp_l_z"], 0.9)
    parked = "".join(f',[{k},"parked",-0.1,-2.0,-1.0,1.0,0.0,0.0,0.0]' for k in (2, 3))
    cols["boxes"] = np.array(
        [
            f'[[0,"active",{x[i]:.6f},{y[i]:.6f},{z[i]:.6f},0.998966,0.000132,-3.2e-05,0.045461],'
            f'[1,"active",-0.745404,0.006212,0.899892,0.998808,0.0,0.0,0.048803]{parked}]'
            for i in range(n)
        ],
        dtype=object,
    )
    return cols


def generate(path: Path, trials: int, mean_frames: int) -> int:
    """A store of ``trials`` trials in two sessions; returns the number of frames."""
    rng = np.random.default_rng(0)
    info = SessionInfo(
        mode="collection",
        operator_id="synthetic",
        seed=0,
        parameters={"recording": {"sampling_rate_hz": RATE_HZ}},
        thresholds={
            "grip_threshold": 0.5,
            "base_linear_threshold": 0.02,
            "base_yaw_threshold": 0.05,
            "joint_rate_threshold": 0.05,
        },
        metric_definitions=METRIC_DEFINITIONS,
        metrics_version=METRICS_VERSION,
    )
    total = 0
    with Store.open(path, writer=True) as store:
        for half in (trials // 2, trials - trials // 2):
            session_id = store.create_session(info)
            for _ in range(half):
                n = int(np.clip(rng.normal(mean_frames, mean_frames / 6), 60, 4 * mean_frames))
                outcome = str(
                    rng.choice(["success", "timeout", "interrupted"], p=[0.75, 0.2, 0.05])
                )
                frames = synthetic_frames(rng, n, oscillate=rng.random() < 0.02)
                trial_id = store.start_trial(
                    session_id, TrialStart(mode="collection", required_boxes=1, time_limit_s=120.0)
                )
                store.add_frames(trial_id, frames_from_columns(frames, session_id, trial_id))
                metrics = compute_trial_metrics(
                    FrameArrays.from_columns(frames), outcome == "success", THRESHOLDS
                )
                end = float(frames["t_sim"][-1])
                store.end_trial(
                    trial_id,
                    TrialEnd(
                        outcome=outcome,
                        interruption_reason="application_quit"
                        if outcome == "interrupted"
                        else None,
                        elapsed_s=end,
                        completion_time_s=end if outcome == "success" else None,
                        boxes_delivered=int(outcome == "success"),
                        score=100 if outcome == "success" else 0,
                        metrics=StoredMetrics.of(metrics),
                    ),
                )
                total += n
            store.end_session(session_id)
    return total


def timed(work: Any) -> tuple[float, Any]:
    """CPU seconds of this process (user + system) for ``work``, and its result: robust to
    other work on a shared machine, and equal to wall time on an idle one (one thread, data
    in the page cache)."""
    start = time.process_time()
    result = work()
    return time.process_time() - start, result


def best_of(repeats: int, work: Any) -> tuple[float, Any]:
    """The fastest of ``repeats`` runs (the machine may be shared) and its result."""
    runs = [timed(work) for _ in range(repeats)]
    return min(runs, key=lambda run: run[0])


def plain_read(path: Path) -> int:
    with Store.open(path, writer=False) as store:
        return sum(len(store.frames(t.trial_id)["t_sim"]) for t in store.trials())


def sqlite_alone(path: Path) -> int:
    conn = connect(path, writer=False)
    try:
        total = " + ".join(f"coalesce({c}, 0)" for c in column_list(FRAME_COLUMNS_READ).split(", "))
        sql = f"SELECT count(*), sum({total}) FROM frames WHERE trial_id = ?"
        ids = [r[0] for r in conn.execute("SELECT trial_id FROM trials")]
        return sum(int(conn.execute(sql, (i,)).fetchone()[0]) for i in ids)
    finally:
        conn.close()


def needed_read(path: Path, use_blocks: bool) -> int:
    source = StoreSource(path, use_blocks=use_blocks)
    try:
        return sum(len(frames) for _, frames in source.frames())
    finally:
        source.close()


def recompute_only(path: Path, limit: int) -> tuple[float, int]:
    """Seconds and frames to audit the first ``limit`` trials whose frames are in memory."""
    source = StoreSource(path)
    try:
        (session,) = {s.session_id: s for s in source.sessions()[:1]}.values()
        rows = {r.trial_id: r for r in source.trials() if r.session_id == session.session_id}
        loaded: list[tuple[Any, FrameArrays]] = []
        for trial_id, frames in source.frames():
            if trial_id in rows:
                loaded.append((rows[trial_id], frames))
            if len(loaded) == limit:
                break
    finally:
        source.close()
    from workcell.audit.config import AuditConfig  # noqa: PLC0415
    from workcell.audit.oscillation import OscillationCriteria  # noqa: PLC0415

    config = AuditConfig()
    criteria = OscillationCriteria.of(config.oscillation, session.rate_hz)
    start = time.process_time()
    for row, frames in loaded:
        audit_trial(row, session, frames, review=None, config=config, criteria=criteria)
    return time.process_time() - start, sum(len(f) for _, f in loaded)


def audit_end_to_end(path: Path, workers: int = 1) -> Any:
    source = StoreSource(path)
    try:
        return run_audit(source, workers=workers)
    finally:
        source.close()


def task_stages(path: Path) -> tuple[int, int]:
    """The extra pass of the task stages: the frames of the trials that delivered nothing
    (the others are ``delivered`` by definition); returns (trials, frames) read."""
    source = StoreSource(path)
    try:
        rows = [r for r in source.trials() if not r.stored["boxes_delivered"]]
        read = source.stage_frames([r.trial_id for r in rows])
        source.trial_conditions([r.trial_id for r in rows])
        assert len(read) == len(rows)
        return len(rows), sum(int(r.stored["n_frames"] or 0) for r in rows)
    finally:
        source.close()


def wall_best_of(repeats: int, work: Any) -> tuple[float, Any]:
    """The shortest wall time of ``repeats`` runs (for work spread over processes)."""
    runs = []
    for _ in range(repeats):
        start = time.perf_counter()
        result = work()
        runs.append((time.perf_counter() - start, result))
    return min(runs, key=lambda run: run[0])


def rate(frames: int, seconds: float) -> str:
    return f"{frames / seconds:>12,.0f} frames/s"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--trials", type=int, default=1000)
    parser.add_argument("--frames", type=int, default=450, help="mean frames per trial")
    parser.add_argument("--store", type=Path, help="reuse (or create) this store")
    parser.add_argument("--repeats", type=int, default=3, help="best of N runs (default 3)")
    args = parser.parse_args()
    cores = pin_to_one_core()
    folder = tempfile.TemporaryDirectory()
    path = args.store or Path(folder.name) / "bench.sqlite"
    if not path.exists():
        seconds, _ = timed(lambda: generate(path, args.trials, args.frames))
        print(f"generated the store in {seconds:.1f} s")
    with Store.open(path, writer=False) as store:
        counts = store.counts()
    print(
        f"store: {counts.trials} trials, {counts.frames:,} frames, "
        f"{path.stat().st_size / 1e6:.0f} MB, one core, best of {args.repeats}"
    )
    best = args.repeats
    t_plain, n = best_of(best, lambda: plain_read(path))
    t_sqlite, _ = best_of(best, lambda: sqlite_alone(path))
    t_rows, _ = best_of(best, lambda: needed_read(path, use_blocks=False))
    t_blocks, _ = best_of(best, lambda: needed_read(path, use_blocks=True))
    t_compute, n_compute = min(recompute_only(path, limit=300) for _ in range(best))
    t_audit, result = best_of(best, lambda: audit_end_to_end(path))
    t_stages, (n_unfinished, n_stage_frames) = best_of(best, lambda: task_stages(path))
    assert result.frames_read == n
    os.sched_setaffinity(0, cores)
    workers = len(cores)
    t_parallel, parallel = wall_best_of(best, lambda: audit_end_to_end(path, workers))
    assert parallel.trials == result.trials and parallel.findings == result.findings
    out = Path(folder.name) / "report"
    t_report, _ = timed(lambda: write_outputs(result, out))
    print(f"plain read (Store.frames, every column)    : {rate(n, t_plain)}")
    print(
        f"SQLite alone, 41 needed columns (no Python): {rate(n, t_sqlite)}  (ceiling of a row read)"
    )
    print(f"audit read, 41 columns from frame rows     : {rate(n, t_rows)}")
    print(f"audit read, frame blocks                   : {rate(n, t_blocks)}")
    print(f"recompute only (metrics + detectors)       : {rate(n_compute, t_compute)}")
    print(f"audit end to end, one process (CPU time)   : {rate(n, t_audit)}")
    label = f"audit end to end, {workers} processes (wall)"
    print(f"{label:43s}: {rate(n, t_parallel)}")
    print(f"end to end / plain read, one process       : {t_plain / t_audit:12.2f}x")
    target = "end to end / 1,000,000 frames/s target"
    print(f"{target}     : {n / t_audit / 1e6:12.2f} one process")
    print(f"{target}     : {n / t_parallel / 1e6:12.2f} {workers} processes")
    print(f"share of one-process time spent reading    : {t_blocks / t_audit:12.0%}")
    print(
        f"task stages, {n_unfinished} trials without a delivery: "
        f"{rate(n_stage_frames, t_stages)} of their frames, "
        f"{t_stages / t_audit:.0%} of the one-process audit"
    )
    print(f"report files (html + 5 figures, json, csv) : {t_report:12.2f} s")
    flagged = sum(bool(t.flags) for t in result.trials)
    print(f"trials flagged / audited                   : {flagged} / {len(result.trials)}")
    folder.cleanup()


if __name__ == "__main__":
    main()

"""Recording cost: the recorder against the simulation it rides on, on one core.

Prints, measured in one run:
- wall time of a headless expert session (collection trials) without and with recording
  into a SQLite store, and the overhead of recording in percent (target: under 5 %);
- the recorder's cost per frame against the cost of simulating one frame period (ratio);
- durable frames per second: frames appended and committed in batches of 0.25 s.

Run: ``.venv/bin/python bench/record.py [--trials N] [--repeats R]``.
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time
from pathlib import Path

from workcell.control.simulation import Simulation
from workcell.expert import ExpertOperator
from workcell.record.recorder import Recorder
from workcell.record.store import Store
from workcell.session.config import SessionConfig, TaskConfig
from workcell.task.runner import SessionRunner


def pin_to_one_core() -> None:
    if hasattr(os, "sched_setaffinity"):
        os.sched_setaffinity(0, {min(os.sched_getaffinity(0))})


def session(config: SessionConfig, store_path: Path | None) -> tuple[float, int, float]:
    """Run the session; returns (wall seconds, frames recorded, sim seconds)."""
    runner = SessionRunner(config, Simulation(config.world), ExpertOperator())
    store = Store.open(store_path, writer=True) if store_path is not None else None
    recorder = Recorder(store, runner) if store is not None else None
    start = time.perf_counter()
    runner.run()
    wall = time.perf_counter() - start
    frames = 0
    if recorder is not None and store is not None:
        recorder.close(interrupted=False)
        frames = recorder.frames_written
        store.close()
    sim_seconds = sum(r.elapsed_s + config.task.countdown_s for r in runner.results)
    return wall, frames, sim_seconds


def durable_rate(store_path: Path, config: SessionConfig, batches: int) -> float:
    """Frames per second through add_frames + commit, 5 frames a batch, from real rows."""
    with Store.open(store_path, writer=False) as reader:
        trial = reader.trials()[0]
        columns = reader.frames(trial.trial_id)
    names = [n for n in columns if n not in ("session_id", "trial_id", "frame_index")]
    batch = {n: columns[n][:5] for n in names}
    target = store_path.with_name("durable.sqlite")
    from workcell.record.recorder import session_info  # noqa: PLC0415
    from workcell.record.records import TrialStart  # noqa: PLC0415

    with Store.open(target, writer=True) as store:
        session_id = store.create_session(session_info(config))
        trial_id = store.start_trial(session_id, TrialStart("collection", 1, 120.0))
        start = time.perf_counter()
        for _ in range(batches):
            store.add_frames(trial_id, batch)
            store.commit()
        return batches * 5 / (time.perf_counter() - start)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--trials", type=int, default=3)
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    pin_to_one_core()
    config = SessionConfig(task=TaskConfig(mode="collection", trials=args.trials))
    without, with_store = [], []
    frames = 0
    sim_seconds = 0.0
    with tempfile.TemporaryDirectory() as folder:
        for k in range(args.repeats):
            without.append(session(config, None)[0])
            wall, frames, sim_seconds = session(config, Path(folder) / f"r{k}.sqlite")
            with_store.append(wall)
        rate = durable_rate(Path(folder) / "r0.sqlite", config, batches=400)
    base, recorded = min(without), min(with_store)
    per_frame = (recorded - base) / frames
    frame_period_cost = base / (sim_seconds * config.recording.sampling_rate_hz)
    print(f"session: {args.trials} expert trials, {sim_seconds:.1f} s simulated, {frames} frames")
    print(f"without recording  : {base:8.3f} s wall (best of {args.repeats})")
    print(f"with recording     : {recorded:8.3f} s wall (best of {args.repeats})")
    print(f"recording overhead : {100 * (recorded - base) / base:8.2f} %   (target < 5 %)")
    print(f"recorder per frame : {per_frame * 1e6:8.1f} us")
    print(f"sim per frame      : {frame_period_cost * 1e6:8.1f} us (one 1/20 s frame period)")
    print(f"recorder / sim     : {per_frame / frame_period_cost:8.3f}")
    print(f"durable frames/s   : {rate:8.0f}  (add_frames + commit, 5 frames a batch)")


if __name__ == "__main__":
    main()

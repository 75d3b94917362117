"""Recording cost: the recorder against the simulation it rides on.

Prints, measured in one run (the same headless expert session each time, same seed):

- the overhead of recording: wall time of the session until its record is durable
  (``runner.run()`` then the session's end, which waits for every frame to be committed),
  with recording through the store writer process (what ``workcell collect`` and
  ``workcell serve`` do) and recording in-process (a :class:`Store` in the simulation's
  thread), against the same session without recording. Variants run interleaved, in a
  rotated order, ``--repeats`` times; each repeat gives one paired ratio per variant, and
  the figure is the median of those ratios with a 95 % bootstrap interval. A second run
  without recording, measured like the others, shows the noise floor of the machine
  (its overhead should be 0 %). Target: under 5 %.
- the recorder's cost per frame against the cost of simulating one frame period (ratio);
- the writer process's CPU time per frame (on the other core);
- durable frames per second: captured frames handed over and committed every 0.25 s.

Not pinned to one core: the writer process uses the machine's second core.

Run: ``.venv/bin/python bench/record.py [--trials N] [--repeats R]``.
"""

from __future__ import annotations

import argparse
import multiprocessing
import os
import resource
import statistics
import tempfile
import time
from pathlib import Path

import numpy as np

from workcell.control.command import Command
from workcell.control.simulation import Simulation
from workcell.expert import ExpertOperator
from workcell.record.frame_capture import FrameCapture, input_from_command
from workcell.record.recorder import Recorder, session_info
from workcell.record.records import TrialEnd, TrialStart
from workcell.record.store import Store
from workcell.record.store_process import StoreProcess
from workcell.session.config import SessionConfig, TaskConfig
from workcell.task.runner import SessionRunner

VARIANTS = ("none", "none again", "process", "inline")
LABELS = {
    "none again": "no recording, again (noise floor)",
    "process": "recording, writer process",
    "inline": "recording, in-process",
}
TARGET = 0.05


def open_store(variant: str, path: Path) -> Store | StoreProcess | None:
    if variant == "process":
        return StoreProcess.open(path)
    if variant == "inline":
        return Store.open(path, writer=True)
    return None


def session(config: SessionConfig, variant: str, path: Path) -> tuple[float, int, float]:
    """Run the session; returns (wall seconds until the record is durable, frames
    recorded, CPU seconds of the writer process over its whole life)."""
    runner = SessionRunner(config, Simulation(config.world), ExpertOperator())
    store = open_store(variant, path)
    recorder = Recorder(store, runner) if store is not None else None
    children = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    runner.run()
    if recorder is not None:
        recorder.close(interrupted=False)  # the session's end: every frame committed
    wall = time.perf_counter() - start
    frames = 0
    if recorder is not None and store is not None:
        assert recorder.failure is None, recorder.failure
        store.close()
        frames = recorder.frames_written
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    writer_cpu = (after.ru_utime + after.ru_stime) - (children.ru_utime + children.ru_stime)
    return wall, frames, writer_cpu


def fresh_session(config: SessionConfig, variant: str, path: Path) -> tuple[float, int, float]:
    """:func:`session` in a new Python process: each run gets its own memory layout (the
    layout of a long-lived process's heap shifts Python code's speed by several percent
    from one run to the next, whatever the variant)."""
    context = multiprocessing.get_context("spawn")
    with context.Pool(1) as pool:
        return pool.apply(session, (config, variant, path))


def median_interval(values: list[float], resamples: int = 4000) -> tuple[float, float, float]:
    """The median and a 95 % percentile-bootstrap interval of it."""
    data = np.asarray(values)
    rng = np.random.default_rng(0)
    medians = np.median(rng.choice(data, size=(resamples, len(data))), axis=1)
    low, high = np.percentile(medians, [2.5, 97.5])
    return float(np.median(data)), float(low), float(high)


def durable_rate(folder: Path, config: SessionConfig, variant: str, batches: int) -> float:
    """Captured frames per second through add_captured_frames + commit, 5 a batch, until
    the writer has committed them all (end_session waits for everything before it)."""
    sim = Simulation(config.world)
    sim.reset(0)
    capture = FrameCapture(sim.world, sim.controller, capacity=5)
    command = Command()
    for k in range(5):
        capture.capture(command, input_from_command(command), t_sim=k / 20, step_wall_ms=1.0)
    frames = capture.take()
    store = open_store(variant, folder / f"durable-{variant}.sqlite")
    assert store is not None
    with store:
        session_id = store.create_session(session_info(config))
        store.prepare_frames(frames.layout)
        trial_id = store.start_trial(session_id, TrialStart("collection", 1, 120.0))
        start = time.perf_counter()
        for _ in range(batches):
            store.add_captured_frames(trial_id, frames)
            store.commit()
        store.end_trial(trial_id, TrialEnd("interrupted", 0.0, 0, 0, "operator_stop"))
        store.end_session(session_id, "interrupted")
        return batches * 5 / (time.perf_counter() - start)


def writer_startup_cpu(folder: Path) -> float:
    """CPU seconds of a writer process that starts, opens a store and exits."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    StoreProcess.open(folder / "idle.sqlite").close()
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return (after.ru_utime + after.ru_stime) - (before.ru_utime + before.ru_stime)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--trials", type=int, default=2)
    parser.add_argument("--repeats", type=int, default=15)
    args = parser.parse_args()
    config = SessionConfig(task=TaskConfig(mode="collection", trials=args.trials))
    walls: dict[str, list[float]] = {v: [] for v in VARIANTS}
    writer_cpu: list[float] = []
    frames = 0
    with tempfile.TemporaryDirectory() as name:
        folder = Path(name)
        for k in range(args.repeats):
            for j in range(len(VARIANTS)):
                variant = VARIANTS[(j + k) % len(VARIANTS)]  # rotated: no variant always first
                path = folder / f"{variant.replace(' ', '-')}{k}.sqlite"
                wall, n, cpu = fresh_session(config, variant, path)
                walls[variant].append(wall)
                if variant == "process":
                    frames = n
                    writer_cpu.append(cpu)
            print(f"  repeat {k + 1}/{args.repeats} done", flush=True)
        startup = writer_startup_cpu(folder)
        process_rate = durable_rate(folder, config, "process", batches=400)
        inline_rate = durable_rate(folder, config, "inline", batches=400)
    base = statistics.median(walls["none"])
    sim_seconds = frames / config.recording.sampling_rate_hz
    frame_period_cost = base / frames
    print(f"machine: {os.cpu_count()} cores, load average {os.getloadavg()[0]:.2f}")
    print(
        f"session: {args.trials} expert trials, {sim_seconds:.1f} s simulated, {frames} frames, "
        f"{args.repeats} repeats"
    )
    print(f"without recording  : {base:8.3f} s wall (median)")
    overhead: dict[str, tuple[float, float, float]] = {}
    for variant in VARIANTS[1:]:
        ratios = [w / b - 1 for w, b in zip(walls[variant], walls["none"], strict=True)]
        overhead[variant] = median_interval(ratios)
        mid, low, high = overhead[variant]
        print(
            f"{LABELS[variant]:34s}: overhead {100 * mid:6.2f} % "
            f"[95 % interval {100 * low:6.2f} .. {100 * high:6.2f}]"
        )
    mid, low, high = overhead["process"]
    verdict = "met" if high < TARGET else "NOT met" if low >= TARGET else "not shown"
    print(
        f"target < {100 * TARGET:.0f} % (writer process): {verdict} "
        "(met: the whole interval is below the target)"
    )
    per_frame = mid * frame_period_cost
    print(f"recorder per frame : {per_frame * 1e6:8.1f} us in the simulation's process")
    print(f"sim per frame      : {frame_period_cost * 1e6:8.1f} us (one 1/20 s frame period)")
    print(f"recorder / sim     : {per_frame / frame_period_cost:8.3f}")
    writer = (statistics.median(writer_cpu) - startup) / frames
    print(f"writer CPU / frame : {writer * 1e6:8.1f} us in the writer process (its start-up apart)")
    print(f"durable frames/s   : {process_rate:8.0f} writer process, {inline_rate:.0f} in-process")


if __name__ == "__main__":
    main()

"""Recording cost: the recorder against the simulation it rides on.

Prints, measured in one run (the same headless expert session each time, same seed, so
every session simulates exactly the same trajectory):

- the overhead of recording: wall time of the session until its record is durable
  (``runner.run()`` then the session's end, which waits for every frame to be committed),
  recording through the store writer process (what ``workcell collect`` and ``workcell
  serve`` do) and recording in-process (an :class:`InProcessStore` in the simulation's thread),
  against the same session without recording.

  The machine's speed drifts by several percent from second to second (other virtual
  machines on the host), and a Python process's memory layout shifts its speed by a few
  percent for its whole life. So the sessions run in ``--blocks`` fresh processes (layouts
  averaged), and in each, ``--repeats`` rounds of back-to-back sessions, one per variant,
  in a random order (drift shared within a round; no variant always follows the same
  one, whose after-effects it would carry), each after a garbage collection. Each round
  gives one paired ratio per variant against its round's session without recording; the
  figure is the median of those ratios with a 95 % bootstrap interval (blocks, then
  rounds in them, resampled). A second session without recording in each round shows
  the noise floor (it should read 0 %). Target: under 5 %, met when the whole interval
  is below it.
- the recorder's cost per frame against the cost of simulating one frame period (ratio);
- the writer process's CPU time per frame (on the other core);
- durable frames per second: captured frames handed over and committed.

Not pinned to one core: the writer process uses the machine's second core.

Run: ``.venv/bin/python bench/record.py [--trials N] [--blocks B] [--repeats R]``.
"""

from __future__ import annotations

import argparse
import gc
import multiprocessing
import os
import statistics
import tempfile
import time
from pathlib import Path

import numpy as np

from workcell.control.command import Command
from workcell.control.simulation import Simulation
from workcell.record.entries import TrialEnd, TrialStart
from workcell.recording.frame_capture import FrameCapture
from workcell.recording.in_process import InProcessStore
from workcell.recording.recorder import Recorder, session_info
from workcell.recording.store_process import StoreProcess
from workcell.session.config import SessionConfig, TaskConfig
from workcell.task.runner import SessionRunner
from workcell.tasks.box_transfer.task import BoxTransfer
from workcell.tasks.elements.expert import ExpertOperator

VARIANTS = ("none", "none again", "process", "inline")
LABELS = {
    "none again": "no recording, again (noise floor)",
    "process": "recording, writer process",
    "inline": "recording, in-process",
}
TARGET = 0.05
MIN_ROUNDS = 10
"""Fewer rounds than this give no verdict: their interval means little."""

Block = dict[str, list[float]]
"""Per variant, the wall seconds of each round's session; "writer cpu" and "frames" too."""


def cpu_seconds(pid: int) -> float:
    """User + system CPU seconds of process ``pid`` so far (Linux /proc; NaN elsewhere)."""
    try:
        fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    except OSError:
        return float("nan")
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def session(
    config: SessionConfig, sim: Simulation, store: InProcessStore | StoreProcess | None
) -> tuple[float, int]:
    """One session on ``sim``, recorded into ``store`` if given: (wall seconds until the
    record is durable, frames recorded). Runner and recorder are put together here rather
    than by :class:`~workcell.recording.recorded_session.RecordedSession`, which builds its
    own world and opens its own store: the rounds share one world and one open store (as a
    server does), so the figure is the recorder's cost alone."""
    runner = SessionRunner(config, sim, ExpertOperator())
    recorder = Recorder(store, runner) if store is not None else None
    start = time.perf_counter()
    runner.run()
    if recorder is not None:
        recorder.close(interrupted=False)  # the session's end: every frame committed
    wall = time.perf_counter() - start
    if recorder is None:
        return wall, 0
    assert recorder.failure is None, recorder.failure
    return wall, recorder.frames_written


def block(config: SessionConfig, repeats: int, first: int, folder: str) -> Block:
    """One fresh process: a session of each variant per round, in a random order (the
    stores stay open for the whole block, as a server keeps its store)."""
    sim = Simulation(config.world, BoxTransfer().scene())
    results: Block = {v: [] for v in (*VARIANTS, "writer cpu", "frames")}
    with (
        StoreProcess.open(Path(folder) / f"process-{first}.sqlite") as process,
        InProcessStore.open(Path(folder) / f"inline-{first}.sqlite", writer=True) as inline,
    ):
        stores = {"none": None, "none again": None, "process": process, "inline": inline}
        session(config, sim, process)  # warm up: first-time costs of every path
        session(config, sim, inline)
        for k in range(first, first + repeats):
            for variant in np.random.default_rng(k).permutation(VARIANTS).tolist():
                gc.collect()  # no variant pays for the garbage of the one before
                before = cpu_seconds(process.pid)
                wall, frames = session(config, sim, stores[variant])
                results[variant].append(wall)
                if variant == "process":
                    results["writer cpu"].append(cpu_seconds(process.pid) - before)
                    results["frames"].append(frames)
    return results


def run_blocks(config: SessionConfig, blocks: int, repeats: int, folder: str) -> list[Block]:
    context = multiprocessing.get_context("spawn")
    out = []
    for b in range(blocks):
        with context.Pool(1) as pool:  # a fresh process: its own memory layout
            out.append(pool.apply(block, (config, repeats, b * repeats, folder)))
        print(f"  block {b + 1}/{blocks} done", flush=True)
    return out


def median_interval(ratios: list[list[float]], resamples: int = 4000) -> tuple[float, float, float]:
    """The median of all ratios and a 95 % percentile-bootstrap interval of it, resampling
    blocks and then the rounds within each drawn block."""
    rng = np.random.default_rng(0)
    groups = [np.asarray(g) for g in ratios]
    medians = np.empty(resamples)
    for r in range(resamples):
        drawn = [groups[i] for i in rng.integers(len(groups), size=len(groups))]
        medians[r] = np.median(np.concatenate([rng.choice(g, size=len(g)) for g in drawn]))
    low, high = np.percentile(medians, [2.5, 97.5])
    return float(np.median(np.concatenate(groups))), float(low), float(high)


def durable_rate(folder: Path, config: SessionConfig, variant: str, batches: int) -> float:
    """Captured frames per second through add_captured_frames + commit, 5 a batch, until
    the writer has committed them all (end_session waits for everything before it)."""
    sim = Simulation(config.world, BoxTransfer().scene())
    sim.reset(0)
    capture = FrameCapture(sim.world, sim.controller, capacity=5)
    command = Command()
    for k in range(5):
        capture.capture(command, None, t_sim=k / 20, step_wall_ms=1.0)
    frames = capture.take()
    path = folder / f"durable-{variant}.sqlite"
    store = (
        StoreProcess.open(path) if variant == "process" else InProcessStore.open(path, writer=True)
    )
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


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--trials", type=int, default=2)
    parser.add_argument("--blocks", type=int, default=8)
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    config = SessionConfig(task=TaskConfig(mode="collection", trials=args.trials))
    with tempfile.TemporaryDirectory() as folder:
        blocks = run_blocks(config, args.blocks, args.repeats, folder)
        process_rate = durable_rate(Path(folder), config, "process", batches=400)
        inline_rate = durable_rate(Path(folder), config, "inline", batches=400)
    base = statistics.median(w for b in blocks for w in b["none"])
    frames = int(blocks[0]["frames"][0])
    sim_seconds = frames / config.recording.sampling_rate_hz
    frame_period_cost = base / frames
    print(f"machine: {os.cpu_count()} cores, load average {os.getloadavg()[0]:.2f}")
    print(
        f"session: {args.trials} expert trials, {sim_seconds:.1f} s simulated, {frames} frames; "
        f"{args.blocks} processes x {args.repeats} rounds"
    )
    print(f"without recording  : {base:8.3f} s wall (median)")
    overhead: dict[str, tuple[float, float, float]] = {}
    for variant in VARIANTS[1:]:
        ratios = [[w / b - 1 for w, b in zip(g[variant], g["none"], strict=True)] for g in blocks]
        overhead[variant] = median_interval(ratios)
        mid, low, high = overhead[variant]
        print(
            f"{LABELS[variant]:34s}: overhead {100 * mid:6.2f} % "
            f"[95 % interval {100 * low:6.2f} .. {100 * high:6.2f}]"
        )
    mid, low, high = overhead["process"]
    verdict = "met" if high < TARGET else "NOT met" if low >= TARGET else "not shown"
    if args.blocks * args.repeats < MIN_ROUNDS:
        verdict = f"no verdict from fewer than {MIN_ROUNDS} rounds"
    print(
        f"target < {100 * TARGET:.0f} % (writer process): {verdict} "
        "(met: the whole interval is below the target)"
    )
    per_frame = mid * frame_period_cost
    print(f"recorder per frame : {per_frame * 1e6:8.1f} us in the simulation's process")
    print(f"sim per frame      : {frame_period_cost * 1e6:8.1f} us (one 1/20 s frame period)")
    print(f"recorder / sim     : {per_frame / frame_period_cost:8.3f}")
    writer = statistics.median(c for b in blocks for c in b["writer cpu"]) / frames
    print(f"writer CPU / frame : {writer * 1e6:8.1f} us in the writer process")
    print(f"durable frames/s   : {process_rate:8.0f} writer process, {inline_rate:.0f} in-process")


if __name__ == "__main__":
    main()

"""Many operators at once against one ``workcell serve --sessions N`` (issue 16).

For each N, a fresh server in its own process on a free localhost port, and N emulated
remote operators, each a real WebSocket client that starts a collection session of its own
(repeated one-box trials) and sends Input messages at a headset's 72 Hz. With the default
``--behaviour expert`` each operator has the expert's behaviour, decided from what the
socket shows (``bench/crowd_operator.py``): it drives up to the box, reaches around it,
squeezes, carries it to the table and sets it down, so every session does a person's work
(driving, grasp contacts, a carried box) and its deliveries count. ``--behaviour circle``
is the older load: the left stick drives back and forth while turning and the right hand
is gripped and moves along a 10 cm circle. Per N, measured together:

- sessions held at real time: each session's real-time factor over the window (sim
  seconds per wall second from ``/api/diagnostics``; held: >= 0.98), its late steps and
  the wall time it dropped;
- input -> state latency over all operators: from sending Input ``seq`` to the first State
  whose ``input_seq`` reaches it, p50/p99 (target p99 <= 100 ms);
- frames lost: gaps in each recorded trial's sim clock, read back from the store after
  the sessions were stopped and merged (target 0), and the recorded frames per session;
- successes: trials the store records as delivered, of the trials that ended;
- server CPU: the server process and its session and store writer processes, cores in
  use and per session, and CPU seconds per simulated second of one session (what a
  session's real-time second costs, also when a busy machine keeps it from real time),
  and the share of it spent in the kernel (waking threads, pipes, sockets);
- the operators' CPU: this bench process's cores over the window (the emulated operators
  share the machine with the server, as they would not in a study).

The baseline, measured in the same run, is N = 1.

Run: ``.venv/bin/python -m bench.crowd [--sessions 1,4,8,16] [--seconds S]`` from the
project root on an otherwise idle machine; every figure is a wall-clock measurement.
"""

from __future__ import annotations

import argparse
import asyncio
import contextlib
import json
import math
import os
import subprocess
import sys
import tempfile
import time
import urllib.request
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from websockets.asyncio.client import ClientConnection, connect

from bench import latency
from bench.crowd_operator import ExpertLikeHeadset
from bench.host_speed import host_speed_line
from bench.latency import LAUNCH, free_port, percentile
from workcell.protocol import messages as m
from workcell.protocol.codec import encode
from workcell.record import Store

INPUT_HZ = 72.0
TASK: dict[str, object] = {"mode": "collection", "countdown_s": 0.0, "time_limit_s": 120.0}
BEHAVIOURS = ("expert", "circle")
HELD_RTF = 0.98


@dataclass(frozen=True)
class Figures:
    sessions: int
    held: int
    min_rtf: float
    late_steps: int
    dropped_s: float
    p50_ms: float
    p99_ms: float
    frames: int
    frames_lost: int
    trials: int
    successes: int
    cores: float
    cpu_per_sim_s: float
    """Server CPU seconds per simulated second of one session: the cost of a session's
    real-time second, whether or not the machine let it keep real time."""
    kernel_share: float
    """Of the server's CPU, the part spent in the kernel (system time)."""
    operator_cores: float
    """Cores the emulated operators (this process) used over the window."""
    load: float


class Operator(latency.Operator):
    """Starts its own session, then sends inputs (see the module's docstring) and times
    when states show them applied."""

    def __init__(
        self, ws: ClientConnection, phase: float, robot: dict[str, float], behaviour: str
    ) -> None:
        super().__init__(ws, INPUT_HZ)
        self.phase = phase
        self.robot = robot
        """``world.robot`` settings of the session (e.g. ``teleop_control_hz``)."""
        self.headset = ExpertLikeHeadset() if behaviour == "expert" else None
        self.lead_s = 0.0
        """The loop's latency as it goes (a low-passed input -> state time), which the
        expert-like operator anticipates."""

    async def start(self, index: int) -> str:
        await self.ws.send(encode(m.Hello(role="operator")))
        settings = {"task": TASK, "operator_id": f"crowd-{index:02d}", "seed": index}
        if self.robot:
            settings["world"] = {"robot": self.robot}
        await self.ws.send(encode(m.StartSession(settings=settings)))
        while True:
            message = json.loads(await asyncio.wait_for(self.ws.recv(), 60))
            if message["type"] == "error":
                raise SystemExit(f"operator {index}: {message['code']}: {message['message']}")
            if message["type"] == "config_rejected":
                problems = "; ".join(p["message"] for p in message["problems"])
                raise SystemExit(f"operator {index}: settings refused: {problems}")
            if message["type"] == "session_started":
                return str(message["session_id"])

    def input(self, seq: int, t: float) -> m.Input:
        if self.headset is not None:
            return self.headset.input(seq, self.lead_s)
        w = 2 * math.pi * 0.25 * t + self.phase
        stick = (0.4 * math.sin(w / 2), 0.5 * math.cos(w))  # drive back and forth, turning
        x, y, z = 0.25 + 0.1 * math.cos(w), 1.1 + 0.1 * math.sin(w), -0.35
        right = m.ControllerState((x, y, z, 1.0, 0.0, 0.0, 0.0), 1.0, 0.0, (0.0, 0.0), 0)
        left = m.ControllerState((-0.25, 1.1, -0.35, 1.0, 0.0, 0.0, 0.0), 0.0, 0.0, stick, 0)
        return m.Input(
            seq=seq,
            t_client=time.time(),
            source="xr",
            headset=(0.0, 1.6, 0.0, 1.0, 0.0, 0.0, 0.0),
            left=left,
            right=right,
        )

    async def send_inputs(self, stop: asyncio.Event) -> None:
        seq = 0
        started = next_at = time.perf_counter()
        while not stop.is_set():
            seq += 1
            message = self.input(seq, time.perf_counter() - started)
            self.sent[seq] = time.perf_counter()
            await self.ws.send(encode(message))
            next_at += self.period
            await asyncio.sleep(max(0.0, next_at - time.perf_counter()))

    async def stop(self) -> None:
        await self.ws.send(encode(m.Stop()))

    def on_message(self, message: dict[str, Any], now: float, sent: float | None) -> None:
        if self.headset is not None:
            self.headset.view.take(message)
        if sent is not None:
            self.lead_s += 0.1 * (now - sent - self.lead_s)


def diagnostics(base: str) -> dict[str, Any]:
    with urllib.request.urlopen(f"{base}/api/diagnostics", timeout=30) as response:
        body: dict[str, Any] = json.loads(response.read())
        return body


def tree_cpu_s(pid: int) -> tuple[float, float]:
    """CPU seconds of process ``pid`` and its descendants (the store writers), from /proc:
    user and system time."""
    parents: dict[int, int] = {}
    ticks: dict[int, tuple[int, int]] = {}
    for entry in os.listdir("/proc"):
        if not entry.isdigit():
            continue
        with contextlib.suppress(OSError):
            fields = Path(f"/proc/{entry}/stat").read_text().rsplit(")", 1)[1].split()
            parents[int(entry)] = int(fields[1])
            ticks[int(entry)] = int(fields[11]), int(fields[12])  # utime, stime
    tree, grew = {pid}, True
    while grew:
        more = {child for child, parent in parents.items() if parent in tree} - tree
        tree |= more
        grew = bool(more)
    hz = os.sysconf("SC_CLK_TCK")
    user = sum(ticks.get(p, (0, 0))[0] for p in tree) / hz
    system = sum(ticks.get(p, (0, 0))[1] for p in tree) / hz
    return user, system


def sim_clock(sims: list[dict[str, Any]]) -> dict[str, float]:
    return {s["session_id"]: s["steps"] * s["control_period_s"] for s in sims}


async def crowd(
    port: int, n: int, seconds: float, server: int, *, robot: dict[str, float], behaviour: str
) -> dict[str, Any]:
    base, url = f"http://127.0.0.1:{port}", f"ws://127.0.0.1:{port}/ws"
    async with contextlib.AsyncExitStack() as stack:
        sockets = [
            await stack.enter_async_context(
                connect(url, subprotocols=[m.SUBPROTOCOL], max_queue=None)  # type: ignore[list-item]
            )
            for _ in range(n)
        ]
        operators = [
            Operator(ws, 2 * math.pi * i / n, robot, behaviour) for i, ws in enumerate(sockets)
        ]
        for i, operator in enumerate(operators):
            await operator.start(i)
        stop = asyncio.Event()
        tasks = [asyncio.create_task(o.receive()) for o in operators]
        tasks += [asyncio.create_task(o.send_inputs(stop)) for o in operators]
        await asyncio.sleep(2.0)  # warm up
        for operator in operators:
            operator.measuring = True
        before = diagnostics(base)
        (user0, sys0), own0, t0 = tree_cpu_s(server), time.process_time(), time.perf_counter()
        await asyncio.sleep(seconds)
        after = diagnostics(base)
        (user1, sys1), own1, t1 = tree_cpu_s(server), time.process_time(), time.perf_counter()
        stop.set()
        for operator in operators:
            await operator.stop()
        await asyncio.sleep(3.0)  # the sessions end and merge
        for task in tasks:
            task.cancel()
    wall = t1 - t0
    cpu = (user1 - user0) + (sys1 - sys0)
    first, last = sim_clock(before["sims"]), sim_clock(after["sims"])
    rtf = [(last[s] - first[s]) / wall for s in last if s in first]
    simulated = sum(last[s] - first[s] for s in last if s in first)
    return {
        "cpu_per_sim_s": cpu / simulated if simulated > 0 else math.nan,
        "kernel_share": (sys1 - sys0) / cpu if cpu > 0 else math.nan,
        "operator_cores": (own1 - own0) / wall,
        "rtf": rtf,
        "late": sum(s["late_steps"] for s in after["sims"]),
        "dropped": sum(s["dropped_s"] for s in after["sims"]),
        "latencies": [x for o in operators for x in o.latencies],
        "cores": cpu / wall,
        "errors": [e for o in operators for e in o.errors],
    }


@dataclass(frozen=True)
class Recorded:
    """What the store holds after the run."""

    sessions: int
    frames: int
    lost: int
    """Frames missing: gaps in a trial's sim clock."""
    trials: int
    """Trials that ended on their own (not stopped by the end of the run)."""
    successes: int


def recorded(store: Path) -> Recorded:
    frames = lost = 0
    with Store.open(store, writer=False) as reader:
        sessions = len(reader.sessions())
        trials = reader.trials()
        ended = [t for t in trials if t.outcome in ("success", "timeout")]
        for trial in trials:
            t = np.asarray(reader.frames(trial.trial_id)["t_sim"], dtype=float)
            frames += len(t)
            if len(t) > 2:
                step = float(np.median(np.diff(t)))
                lost += int(np.sum(np.round(np.diff(t) / step) - 1))
    successes = sum(t.outcome == "success" for t in ended)
    return Recorded(sessions, frames, lost, len(ended), successes)


def measure(
    n: int,
    seconds: float,
    robot: dict[str, float],
    behaviour: str,
    ray: str | None,
    *,
    compression: bool = False,
    launch: str = LAUNCH,
    env: dict[str, str] | None = None,
) -> Figures:
    """One N measured on a fresh server started by ``launch`` (a ``python -c`` script that
    runs ``workcell serve`` with the arguments it is given), ``env`` added to its
    environment."""
    with tempfile.TemporaryDirectory() as tmp:
        store = Path(tmp) / "crowd.sqlite"
        port = free_port()
        environment = {**os.environ, "MUJOCO_GL": os.environ.get("MUJOCO_GL", "egl")}
        environment.update(env or {})
        seats = n if ray is None else max(n, 2)  # --ray needs two seats or more
        arguments = ["--port", str(port), "--store", str(store), "--sessions", str(seats)]
        arguments += ["--no-admission"]  # every session at once: the load is what is measured
        if ray is not None:
            arguments += ["--ray", ray]
        if compression:
            arguments.append("--ws-compression")
        process = subprocess.Popen(
            [sys.executable, "-c", launch, *arguments],
            stdout=subprocess.DEVNULL,
            stderr=subprocess.PIPE,
            env=environment,
        )
        try:
            deadline = time.monotonic() + 120  # Ray takes a while to start
            while True:
                try:
                    diagnostics(f"http://127.0.0.1:{port}")
                    break
                except OSError:
                    if time.monotonic() > deadline or process.poll() is not None:
                        raise SystemExit("the server did not start") from None
                    time.sleep(0.1)
            result = asyncio.run(
                crowd(port, n, seconds, process.pid, robot=robot, behaviour=behaviour)
            )
        finally:
            process.terminate()
            process.wait(60)
        record = recorded(store)
    if result["errors"]:
        print(f"  errors the operators heard: {sorted(set(result['errors']))[:5]}")
    rtf, latencies = result["rtf"], result["latencies"]
    assert record.sessions == n, f"{record.sessions} sessions recorded, {n} driven"
    return Figures(
        sessions=n,
        held=sum(r >= HELD_RTF for r in rtf),
        min_rtf=min(rtf),
        late_steps=result["late"],
        dropped_s=result["dropped"],
        p50_ms=1000 * percentile(latencies, 0.5),
        p99_ms=1000 * percentile(latencies, 0.99),
        frames=record.frames // n,
        frames_lost=record.lost,
        trials=record.trials,
        successes=record.successes,
        cores=result["cores"],
        cpu_per_sim_s=result["cpu_per_sim_s"],
        kernel_share=result["kernel_share"],
        operator_cores=result["operator_cores"],
        load=os.getloadavg()[0],
    )


def report(rows: list[Figures], seconds: float) -> None:
    print(f"\n{seconds:g} s per N, operators at {INPUT_HZ:g} Hz; ratios against N = 1")
    print(
        "sessions  held at RT  min RTF  late steps  dropped s   input->state p50 (ratio)"
        "   p99 (ratio)   frames/session  lost   delivered/trials   cores (per session)"
        "  CPU s per session's sim s  kernel  operators' cores  load"
    )
    base = rows[0]
    for r in rows:
        print(
            f"{r.sessions:8d}  {r.held:4d}/{r.sessions:<5d}  {r.min_rtf:7.3f}  {r.late_steps:10d}"
            f"  {r.dropped_s:9.2f}   {r.p50_ms:8.1f} ms ({r.p50_ms / base.p50_ms:4.2f})"
            f"   {r.p99_ms:6.1f} ms ({r.p99_ms / base.p99_ms:4.2f})   {r.frames:14d}"
            f"  {r.frames_lost:4d}   {r.successes:7d}/{r.trials:<8d}"
            f"   {r.cores:5.2f} ({r.cores / r.sessions:5.3f})"
            f"         {r.cpu_per_sim_s:5.3f}"
            f"              {100 * r.kernel_share:4.1f} %  {r.operator_cores:5.2f}"
            f"             {r.load:4.1f}"
        )
    held = [
        r.sessions for r in rows if r.held == r.sessions and r.p99_ms <= 100 and not r.frames_lost
    ]
    print(
        f"most sessions held at real time with p99 <= 100 ms and no frame lost: "
        f"{max(held, default=0)} (target >= 16)"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sessions", default="1,4,8,16", help="values of N")
    parser.add_argument("--seconds", type=float, default=60.0, help="measured window per N")
    parser.add_argument(
        "--behaviour",
        choices=BEHAVIOURS,
        default="expert",
        help="expert: deliver boxes as the expert does; circle: drive and wave a hand",
    )
    parser.add_argument(
        "--control-hz", type=float, help="world.robot.teleop_control_hz of every session"
    )
    parser.add_argument("--ik-hz", type=float, help="world.robot.teleop_ik_hz of every session")
    parser.add_argument(
        "--ray",
        metavar="ADDRESS",
        help="run the sessions as Ray actors (workcell serve --ray; 'local': Ray on this machine)",
    )
    parser.add_argument(
        "--ws-compression",
        action="store_true",
        help="serve with --ws-compression (the operators offer permessage-deflate, as browsers do)",
    )
    args = parser.parse_args()
    counts = [int(n) for n in args.sessions.split(",")]
    robot = {
        key: value
        for key, value in (("teleop_control_hz", args.control_hz), ("teleop_ik_hz", args.ik_hz))
        if value is not None
    }
    if robot:
        print(
            "sessions run with world.robot " + ", ".join(f"{k} = {v:g}" for k, v in robot.items())
        )
    print(
        f"operators: {args.behaviour}; sessions in "
        + (f"Ray actors ({args.ray})" if args.ray else "processes")
        + ("; messages compressed" if args.ws_compression else "")
    )
    print(f"{os.cpu_count()} cores; load average {os.getloadavg()[0]:.1f}")
    print(host_speed_line(), flush=True)  # runs of other hours compare by it
    rows = []
    for n in counts:
        print(f"N = {n} ...", flush=True)
        rows.append(
            measure(
                n, args.seconds, robot, args.behaviour, args.ray, compression=args.ws_compression
            )
        )
    report(rows, args.seconds)
    print(host_speed_line())


if __name__ == "__main__":
    main()

"""Source trials recorded through the teleop path: ``workcell serve`` and a scripted
remote operator over its WebSocket (issue 34, item 3).

The operator is ``bench/crowd_operator.py``'s :class:`ExpertLikeHeadset`: it sees only
what a browser sees and sends an emulated headset's Input messages at 72 Hz (clutch grips,
triggers, thumbsticks, controller poses moved step by step toward where it wants the
hands), so its trials carry what a person's do and the expert's do not: arms that follow
only while a grip is held, hands that reach their targets through repeated small
corrections, waits for the loop's latency, and re-tries of a squeeze that did not take.
The session runs at real time, so recording a trial takes its sim time in wall time.

    .venv/bin/python -m bench.teleop_sources --out teleop.sqlite --trials 10
"""

from __future__ import annotations

import argparse
import asyncio
import json
import os
import subprocess
import sys
import time
import urllib.request
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from websockets.asyncio.client import connect

from bench.crowd_operator import ExpertLikeHeadset
from bench.latency import free_port
from workcell.protocol import messages as m
from workcell.protocol.codec import encode

INPUT_PERIOD_S = 1 / 72
STALL_S = 60.0
"""Give up when the simulated time (each trial's clock) stands still this long (wall s)."""
OPERATOR_ID = "teleop-script"


@dataclass(frozen=True)
class Recorded:
    reason: str
    """Why the session ended (``completed`` when every trial ran)."""
    trials: int
    successes: int


def session_settings(trials: int, seed: int, world: dict[str, Any] | None = None) -> dict[str, Any]:
    """A collection session of ``trials`` one-box trials that start at once."""
    settings: dict[str, Any] = {
        "task": {"mode": "collection", "trials": trials, "countdown_s": 0.0, "time_limit_s": 120.0},
        "seed": seed,
        "operator_id": OPERATOR_ID,
    }
    if world:
        settings["world"] = world
    return settings


async def drive_session(url: str, settings: dict[str, Any], lead_s: float = 0.05) -> Recorded:
    """Start a session with ``settings`` on the server at ``url`` (``ws://.../ws``) and
    operate it until it ends."""
    async with connect(url, subprotocols=[m.SUBPROTOCOL], max_queue=None) as ws:  # type: ignore[list-item]
        await ws.send(encode(m.Hello(role="operator")))
        await ws.send(encode(m.StartSession(settings=settings)))
        headset = ExpertLikeHeadset()
        ended: dict[str, Any] = {}
        clock = {"t_sim": -1.0, "at": time.monotonic()}

        async def listen() -> None:
            async for text in ws:
                message = json.loads(text)
                kind = message["type"]
                if kind in ("error", "config_rejected"):
                    raise RuntimeError(f"the server refused the session: {message}")
                headset.view.take(message)
                if kind == "state" and message["t_sim"] != clock["t_sim"]:  # per trial
                    clock.update(t_sim=message["t_sim"], at=time.monotonic())
                if kind == "session_ended":
                    ended.update(message)
                    return

        listener = asyncio.create_task(listen())
        seq = 0
        while not listener.done() and time.monotonic() - clock["at"] < STALL_S:
            seq += 1
            await ws.send(encode(headset.input(seq, lead_s=lead_s)))
            await asyncio.sleep(INPUT_PERIOD_S)
        if not listener.done():
            listener.cancel()
            raise RuntimeError(f"the simulated time stood still at {clock['t_sim']} s")
        listener.result()  # raises what the listener raised
        return Recorded(str(ended["reason"]), int(ended["trials"]), int(ended["successes"]))


def record(store: Path, trials: int, seed: int, world: dict[str, Any] | None = None) -> Recorded:
    """Record ``trials`` teleop trials into ``store`` through a ``workcell serve`` of its own
    (a process on a free localhost port, admission off), then stop the server."""
    port = free_port()
    environment = {**os.environ, "MUJOCO_GL": os.environ.get("MUJOCO_GL", "egl")}
    command = [sys.executable, "-m", "workcell", "serve", "--port", str(port)]
    command += ["--store", str(store), "--no-admission"]
    server = subprocess.Popen(
        command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, env=environment
    )
    try:
        _wait_for(f"http://127.0.0.1:{port}/api/diagnostics", server)
        recorded = asyncio.run(
            drive_session(f"ws://127.0.0.1:{port}/ws", session_settings(trials, seed, world))
        )
        time.sleep(2.0)  # the session's store shard is merged after it ended
        return recorded
    finally:
        server.terminate()
        try:
            server.wait(60)
        except subprocess.TimeoutExpired:
            server.kill()
            server.wait()


def _wait_for(url: str, process: subprocess.Popen[bytes]) -> None:
    deadline = time.monotonic() + 120
    while True:
        try:
            with urllib.request.urlopen(url, timeout=10):
                return
        except OSError:
            if process.poll() is not None:
                error = process.stderr.read().decode() if process.stderr else ""
                raise SystemExit(f"workcell serve did not start: {error[-2000:]}") from None
            if time.monotonic() > deadline:
                raise SystemExit("workcell serve did not answer within 120 s") from None
            time.sleep(0.2)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, required=True, help="the store to record into")
    parser.add_argument("--trials", type=int, default=10)
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args()
    recorded = record(args.out, args.trials, args.seed)
    print(
        f"{recorded.successes} of {recorded.trials} teleop trials succeeded "
        f"(session {recorded.reason}); recorded in {args.out}"
    )


if __name__ == "__main__":
    main()

"""Admission by measured headroom on this machine (issue 36): a real ``workcell serve
--sessions N`` with the default admission, and N operators that each ask for a session one
after another (a real WebSocket each, a practice session with a long limit). Prints, for
each operator, whether its session started or waits in line (and the server's words), then
every running session's measured recent real-time factor and cores, the rule's budget, and
the admin warning the figures would give. Every figure is a wall-clock measurement.

Run: ``.venv/bin/python -m bench.admission [--sessions 3] [--seconds 12]`` from the
project root.
"""

from __future__ import annotations

import argparse
import asyncio
import json
import os
import subprocess
import sys
import tempfile
import time
import urllib.request
from pathlib import Path
from typing import Any

from websockets.asyncio.client import connect

from bench.latency import free_port
from workcell.protocol import messages as m
from workcell.protocol.codec import decode_server, encode
from workcell.server.admission import behind_real_time

SETTINGS: dict[str, object] = {"task": {"countdown_s": 0.0, "time_limit_s": 600.0}}


def diagnostics(port: int) -> dict[str, Any]:
    with urllib.request.urlopen(f"http://127.0.0.1:{port}/api/diagnostics", timeout=5) as r:
        answer: dict[str, Any] = json.loads(r.read())
    return answer


async def operator(port: int, index: int, told: list[str]) -> None:
    """Ask for a session; note what the server said; hold the link open."""
    async with connect(f"ws://127.0.0.1:{port}/ws", subprotocols=[m.SUBPROTOCOL]) as ws:  # type: ignore[list-item]
        await ws.send(encode(m.Hello(role="operator")))
        await ws.send(encode(m.StartSession(settings=SETTINGS)))
        while True:
            message = decode_server(await ws.recv())
            if isinstance(message, m.SessionStarted):
                told[index] = f"started {message.session_id}"
            elif isinstance(message, m.Queued):
                told[index] = message.message
            elif isinstance(message, m.Error):
                told[index] = f"error: {message.message}"


async def run(port: int, sessions: int, seconds: float) -> None:
    told = ["(nothing yet)"] * sessions
    tasks = []
    for index in range(sessions):
        tasks.append(asyncio.create_task(operator(port, index, told)))
        await asyncio.sleep(seconds / sessions)  # one after another, each measured first
    await asyncio.sleep(4.0)
    figures = diagnostics(port)
    for index, text in enumerate(told):
        print(f"operator {index + 1}: {text}")
    for sim in figures["sims"]:
        print(
            f"seat {sim['seat']}: recent real-time factor {sim['real_time_factor']:.3f}, "
            f"{sim['cores']:.2f} cores, {sim['late_steps']} late steps"
        )
    warning = behind_real_time([s["real_time_factor"] for s in figures["sims"]])
    print(f"cores budget: {os.cpu_count()} (this machine); admin warning: {warning or '(none)'}")
    for task in tasks:
        task.cancel()
    await asyncio.gather(*tasks, return_exceptions=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sessions", type=int, default=3)
    parser.add_argument(
        "--seconds", type=float, default=12.0, help="between the first and last ask"
    )
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        port = free_port()
        store = Path(tmp) / "admission.sqlite"
        command = [sys.executable, "-m", "workcell", "serve", "--port", str(port)]
        command += ["--store", str(store), "--sessions", str(args.sessions)]
        env = {**os.environ, "MUJOCO_GL": os.environ.get("MUJOCO_GL", "egl")}
        server = subprocess.Popen(
            command, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env
        )
        try:
            deadline = time.monotonic() + 60
            while True:
                try:
                    diagnostics(port)
                    break
                except OSError:
                    if time.monotonic() > deadline or server.poll() is not None:
                        raise SystemExit("the server did not start") from None
                    time.sleep(0.2)
            asyncio.run(run(port, args.sessions, args.seconds))
        finally:
            server.terminate()
            server.wait(60)


if __name__ == "__main__":
    main()

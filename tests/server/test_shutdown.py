"""``workcell serve`` in its own process: SIGTERM ends the running trial application_quit."""

from __future__ import annotations

import asyncio
import contextlib
import os
import re
import signal
import subprocess
import sys
import time
from pathlib import Path

from websockets.asyncio.client import connect
from websockets.exceptions import ConnectionClosed

from tests.server.harness import FAST_SETTINGS
from workcell.protocol import messages as m
from workcell.protocol.codec import decode_server, encode
from workcell.record.store import Store

LAUNCH = """
import argparse, sys
from workcell.cli import serve
parser = argparse.ArgumentParser()
serve.register(parser.add_subparsers())
args = parser.parse_args(["serve", *sys.argv[1:]])
sys.exit(args.func(args))
"""


def _free_port() -> int:
    import socket

    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def test_sigterm_closes_the_running_trial_as_application_quit(tmp_path: Path) -> None:
    store = tmp_path / "store.sqlite"
    port = _free_port()
    env = {**os.environ, "MUJOCO_GL": "egl"}
    process = subprocess.Popen(
        [sys.executable, "-c", LAUNCH, "--store", str(store), "--port", str(port)],
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
        env=env,
    )
    try:
        assert process.stdout is not None
        line = process.stdout.readline()
        assert re.search(rf"open http://127\.0\.0\.1:{port}/", line), line
        heard = asyncio.run(_start_then_terminate(port, process))
        output, _ = process.communicate(timeout=30)
    finally:
        if process.poll() is None:
            process.kill()
    assert process.returncode == 128 + signal.SIGTERM, output  # 143: the shells' convention
    with Store.open(store, writer=False) as reader:
        (session,) = reader.sessions()
        (trial,) = reader.trials()
    assert trial.outcome == "interrupted" and trial.interruption_reason == "application_quit"
    assert session.status == "interrupted"
    assert heard == "application_quit"  # the connected operator was told why


async def _start_then_terminate(port: int, process: subprocess.Popen[str]) -> str | None:
    """Start a session, send SIGTERM while still connected; the SessionEnded reason."""
    deadline = time.monotonic() + 20
    while True:
        try:
            ws = await connect(f"ws://127.0.0.1:{port}/ws", subprotocols=[m.SUBPROTOCOL])  # type: ignore[list-item]
            break
        except OSError:
            assert time.monotonic() < deadline
            await asyncio.sleep(0.1)
    async with ws:
        await ws.send(encode(m.Hello(role="operator")))
        await ws.send(encode(m.StartSession(settings=FAST_SETTINGS)))
        while not isinstance(decode_server(await ws.recv()), m.State):
            pass
        process.send_signal(signal.SIGTERM)
        with contextlib.suppress(ConnectionClosed):
            while True:
                message = decode_server(await asyncio.wait_for(ws.recv(), 20))
                if isinstance(message, m.SessionEnded):
                    return message.reason
    return None

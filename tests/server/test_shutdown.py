"""``workcell serve`` in its own process: SIGTERM ends the running trial application_quit;
a SIGKILL of the server alone, which closes nothing, leaves it recorded as a crash."""

from __future__ import annotations

import asyncio
import contextlib
import os
import re
import signal
import socket
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
from workcell.record.verify import verify_store

LAUNCH = """
import argparse, sys
from workcell.cli import serve
parser = argparse.ArgumentParser()
serve.register(parser.add_subparsers())
args = parser.parse_args(["serve", *sys.argv[1:]])
sys.exit(args.func(args))
"""


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def _serve(store: Path, port: int) -> subprocess.Popen[str]:
    """``workcell serve`` on ``store`` and ``port``, once it says where it listens."""
    env = {**os.environ, "MUJOCO_GL": "egl"}
    process = subprocess.Popen(
        [sys.executable, "-c", LAUNCH, "--store", str(store), "--port", str(port)],
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
        env=env,
    )
    assert process.stdout is not None
    line = process.stdout.readline()
    assert re.search(rf"open http://127\.0\.0\.1:{port}/", line), line
    return process


def test_sigterm_closes_the_running_trial_as_application_quit(tmp_path: Path) -> None:
    store = tmp_path / "store.sqlite"
    port = _free_port()
    process = _serve(store, port)
    try:
        heard = asyncio.run(_start_then_signal(port, process, signal.SIGTERM))
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
    assert f"recorded 1 session, 1 trial (1 interrupted) into {store}" in output, output


def test_ctrl_c_prints_what_the_run_recorded(tmp_path: Path) -> None:
    store = tmp_path / "store.sqlite"
    port = _free_port()
    process = _serve(store, port)
    try:
        heard = asyncio.run(_start_then_signal(port, process, signal.SIGINT))
        output, _ = process.communicate(timeout=30)
    finally:
        if process.poll() is None:
            process.kill()
    assert heard == "application_quit"
    assert process.returncode == 128 + signal.SIGINT, output
    last = output.strip().splitlines()[-1]
    assert (
        last == f"workcell serve: stopped; recorded 1 session, 1 trial (1 interrupted) into {store}"
    )


def test_a_busy_port_is_one_line_and_exit_2_with_no_link(tmp_path: Path) -> None:
    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        port = int(taken.getsockname()[1])
        done = subprocess.run(
            [
                sys.executable,
                "-m",
                "workcell",
                "serve",
                "--store",
                str(tmp_path / "s.sqlite"),
                "--port",
                str(port),
            ],
            capture_output=True,
            text=True,
            timeout=60,
            check=False,
            env={**os.environ, "MUJOCO_GL": "egl"},
        )
    assert done.returncode == 2, done
    assert done.stdout == ""  # no link that would open nothing
    (line,) = done.stderr.strip().splitlines()
    assert f"--port = {port}: 127.0.0.1:{port} is already in use" in line
    assert "--port" in line and "Traceback" not in done.stderr
    assert not (tmp_path / "s.sqlite").exists()


def test_a_sigkill_of_the_server_alone_leaves_its_trial_recorded_as_a_crash(
    tmp_path: Path,
) -> None:
    """The session's process outlives the server and finds its pipe closed without being
    asked to stop: not an orderly shutdown (application_quit) but a crash."""
    store = tmp_path / "store.sqlite"
    port = _free_port()
    process = _serve(store, port)
    try:
        heard = asyncio.run(_start_then_signal(port, process, signal.SIGKILL))
        process.communicate(timeout=30)
    finally:
        if process.poll() is None:
            process.kill()
    assert heard is None  # nobody was left to tell the operator
    deadline = time.monotonic() + 60
    while True:  # the session's process closes what it recorded, then exits
        with Store.open(store, writer=False) as reader:
            (session,) = reader.sessions()
            trials = reader.trials()
        if session.status != "running":
            break
        assert time.monotonic() < deadline, "the session's process did not close the session"
        time.sleep(0.1)
    assert [(t.outcome, t.interruption_reason) for t in trials] == [
        ("interrupted", "crash_recovered")
    ]
    assert verify_store(store) == []


async def _start_then_signal(
    port: int, process: subprocess.Popen[str], signum: signal.Signals
) -> str | None:
    """Start a session, send ``signum`` while still connected; the SessionEnded reason
    (None: the connection closed first)."""
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
        process.send_signal(signum)
        with contextlib.suppress(ConnectionClosed):
            while True:
                message = decode_server(await asyncio.wait_for(ws.recv(), 20))
                if isinstance(message, m.SessionEnded):
                    return message.reason
    return None

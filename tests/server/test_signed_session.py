"""``workcell serve --key FILE``: a live session's hash chain is signed by the store writer
process, and ``verify --key`` checks it, also after a session's process was killed and its
shard recovered when it was merged."""

from __future__ import annotations

import asyncio
import os
import secrets
import signal
from pathlib import Path

import pytest

from tests.server.harness import FAST_SETTINGS, RunningServer, client, running_server
from workcell.errors import ConfigError
from workcell.protocol import messages as m
from workcell.record import Store
from workcell.record.chain import ChainKey
from workcell.record.verify import verify_store
from workcell.server.options import ServerOptions


def test_a_live_session_is_signed_with_the_servers_key(tmp_path: Path) -> None:
    key_file = tmp_path / "serve.key"
    key_file.write_text(secrets.token_hex(32))
    key = ChainKey.from_file(key_file)

    async def scenario(server: RunningServer) -> None:
        async with client(server) as operator:
            await operator.hello()
            await operator.send(m.StartSession(settings=FAST_SETTINGS))
            await operator.wait_for(lambda x: isinstance(x, m.State) and x.t_sim > 0.5)
            await operator.send(m.Stop())
            await operator.wait_for(lambda x: isinstance(x, m.SessionEnded))

    with running_server(tmp_path, key_file=key_file) as server:
        asyncio.run(scenario(server))
        store = server.options.store
    with Store.open(store, writer=False) as reader:
        links = reader.chain()
    assert [link.kind for link in links] == ["start", "trial", "end"]
    assert {link.key_id for link in links} == {key.key_id}
    assert verify_store(store, key=key) == []
    assert verify_store(store, key=ChainKey(b"x" * 32)) != []


def test_a_bad_key_file_is_refused_before_serving(tmp_path: Path) -> None:
    (tmp_path / "short.key").write_text("short")
    with pytest.raises(ConfigError, match=r"--key: key file .* holds 5 bytes"):
        ServerOptions(key_file=tmp_path / "short.key")


def test_a_killed_session_of_a_keyed_server_is_recovered_signed(tmp_path: Path) -> None:
    key_file = tmp_path / "serve.key"
    key_file.write_text(secrets.token_hex(32))
    key = ChainKey.from_file(key_file)

    async def scenario(server: RunningServer) -> None:
        async with client(server) as operator:
            await operator.hello()
            await operator.send(m.StartSession(settings=FAST_SETTINGS))
            await operator.wait_for(lambda x: isinstance(x, m.State) and x.t_sim > 0.5)
            doomed = server.seats.conductors["1"].session
            assert doomed is not None and doomed.pid is not None
            os.kill(doomed.pid, signal.SIGKILL)
            ended = await operator.wait_for(lambda x: isinstance(x, m.SessionEnded), timeout=30)
            assert isinstance(ended, m.SessionEnded) and ended.reason == "error"

    with running_server(tmp_path, key_file=key_file, max_sessions=2) as server:
        asyncio.run(scenario(server))
        store = server.options.store
    with Store.open(store, writer=False) as reader:
        (trial,) = reader.trials()
        links = reader.chain()
    assert (trial.outcome, trial.interruption_reason) == ("interrupted", "crash_recovered")
    assert [link.kind for link in links] == ["start", "trial", "end"]
    assert {link.key_id for link in links} == {key.key_id}
    assert verify_store(store, key=key) == []

"""Several operators at once (``workcell serve --sessions N``): each drives a session of
its own over a real socket, recorded into a shard merged into the store when it ends; a
spectator watches the seat it names; an operator beyond N is told the server is full; a
session whose simulation fails ends alone; a dropped operator takes back its own seat."""

from __future__ import annotations

import asyncio
import contextlib
import os
import shutil
import signal
from pathlib import Path
from typing import Any

import pytest

from tests.server.harness import FAST_SETTINGS, Client, RunningServer, client, running_server
from workcell.errors import ConfigError
from workcell.protocol import messages as m
from workcell.record import Store
from workcell.record.verify import verify_store
from workcell.server import session_relay
from workcell.server.options import ServerOptions
from workcell.server.seats import Seats
from workcell.server.shards import shard_folder


async def _start(operator: Client, operator_id: str) -> m.SessionStarted:
    settings: dict[str, Any] = {**FAST_SETTINGS, "operator_id": operator_id}
    await operator.send(m.StartSession(settings=settings))
    started = await operator.wait_for(lambda x: isinstance(x, m.SessionStarted))
    assert isinstance(started, m.SessionStarted)
    return started


async def _drive(operator: Client, inputs: int) -> int:
    """Send ``inputs`` inputs and wait for the State that applied the last."""
    last = 0
    for _ in range(inputs):
        last = await operator.input()
        await asyncio.sleep(0.02)
    await operator.wait_for(lambda x: isinstance(x, m.State) and x.input_seq == last)
    return last


async def _stop(operator: Client) -> m.SessionEnded:
    await operator.send(m.Stop())
    ended = await operator.wait_for(lambda x: isinstance(x, m.SessionEnded), timeout=30)
    assert isinstance(ended, m.SessionEnded)
    return ended


def _recorded(server: RunningServer) -> dict[str, list[tuple[str | None, str | None]]]:
    """Per operator id: (outcome, interruption reason) of each trial in the store."""
    store = server.options.store
    assert verify_store(store) == []
    with Store.open(store, writer=False) as reader:
        operators = {s.session_id: s.operator_id for s in reader.sessions()}
        recorded: dict[str, list[tuple[str | None, str | None]]] = {
            o: [] for o in operators.values()
        }
        for trial in reader.trials():
            recorded[operators[trial.session_id]].append((trial.outcome, trial.interruption_reason))
    return recorded


def test_four_operators_drive_four_sessions_at_once(tmp_path: Path) -> None:
    async def scenario() -> None:
        with running_server(tmp_path, max_sessions=4) as server:
            async with (
                client(server) as a,
                client(server) as b,
                client(server) as c,
                client(server) as d,
                client(server) as late,
                client(server) as watcher,
            ):
                operators = (a, b, c, d)
                welcomes = [await o.hello() for o in operators]
                assert [(w.role, w.seat) for w in welcomes] == [
                    ("operator", "1"),
                    ("operator", "2"),
                    ("operator", "3"),
                    ("operator", "4"),
                ]
                started = [await _start(o, f"person-{i}") for i, o in enumerate(operators)]
                assert len({s.session_id for s in started}) == 4

                # a fifth operator watches and is told why
                turned_away = await late.hello()
                assert turned_away.role == "spectator" and turned_away.resume_token is None
                full = await late.wait_for(lambda x: isinstance(x, m.Error))
                assert isinstance(full, m.Error) and full.code == "server_full"
                assert "all 4 seats have an operator" in full.message
                assert "--sessions 4" in full.message

                # a spectator watches the seat it names: seat 3's session, nobody else's
                seen = await watcher.hello("spectator", seat="3")
                assert (seen.role, seen.seat) == ("spectator", "3")
                assert seen.session_id == started[2].session_id
                await _drive(c, 10)

                # all four drive at once, and each sees its own inputs applied
                await asyncio.gather(*(_drive(o, 20) for o in operators))
                assert (a.seq, c.seq) == (20, 30)  # the watcher sees c's 30th: seat 3's
                await watcher.wait_for(lambda x: isinstance(x, m.State) and x.input_seq == 30)

                ended = await asyncio.gather(*(_stop(o) for o in operators))
                assert [e.session_id for e in ended] == [s.session_id for s in started]
                assert all(e.reason == "operator_stop" and e.detail == "" for e in ended)

            recorded = _recorded(server)
            assert recorded == {f"person-{i}": [("interrupted", "operator_stop")] for i in range(4)}
            assert list(shard_folder(server.options.store).glob("*")) == []
            assert list(server.seats.conductors) == ["1"]  # later seats went once idle

    asyncio.run(scenario())


def test_a_dead_simulation_ends_only_its_own_session(tmp_path: Path) -> None:
    async def scenario() -> None:
        with running_server(tmp_path, max_sessions=2) as server:
            async with client(server) as a, client(server) as b, client(server) as watcher:
                await a.hello()
                await b.hello()
                await _start(a, "steady")
                started = await _start(b, "doomed")
                await watcher.hello("spectator", seat="2")
                doomed = server.seats.conductors["2"].session
                assert doomed is not None and doomed.pid is not None
                await _drive(b, 5)
                os.kill(doomed.pid, signal.SIGKILL)  # as a crash in native code would
                ended = await b.wait_for(lambda x: isinstance(x, m.SessionEnded), timeout=30)
                assert isinstance(ended, m.SessionEnded)
                assert ended.session_id == started.session_id
                assert ended.reason == "error"
                assert ended.detail.startswith("the session's process died (killed by SIGKILL)")
                told = await watcher.wait_for(lambda x: isinstance(x, m.SessionEnded))
                assert told == ended

                # seat 1 never noticed: it still runs and applies its operator's inputs
                await _drive(a, 10)
                assert all(not isinstance(x, m.SessionEnded) for x in a.received), (
                    "seat 1 heard seat 2's end"
                )
                assert (await _stop(a)).reason == "operator_stop"

            recorded = _recorded(server)
            assert recorded == {
                "steady": [("interrupted", "operator_stop")],
                # left open by the failed thread, recovered when its shard was merged
                "doomed": [("interrupted", "crash_recovered")],
            }

    asyncio.run(scenario())


def test_a_frozen_simulation_holds_up_no_other_session_and_is_killed_when_it_will_not_stop(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A session's process that stops reading its pipe (here stopped with SIGSTOP, as a
    hang in native code would leave it) while its operator keeps sending: the server still
    serves the other session at once, and when the frozen one is asked to stop and does
    not, the server kills it after the grace and ends it alone, its record recovered."""
    monkeypatch.setattr(session_relay, "STOP_GRACE_S", 3.0)

    async def scenario() -> None:
        with running_server(tmp_path, max_sessions=2) as server:
            async with client(server) as a, client(server) as b:
                await a.hello()
                await b.hello()
                await _start(a, "steady")
                started = await _start(b, "frozen")
                frozen = server.seats.conductors["2"].session
                assert frozen is not None and frozen.pid is not None
                await _drive(b, 3)
                os.kill(frozen.pid, signal.SIGSTOP)
                try:
                    # far more than its pipe holds (about 64 KiB, some 200 inputs)
                    for _ in range(500):
                        await b.input()
                        await asyncio.sleep(0.005)
                    # the newest input waits, in place of the others; nothing else
                    assert frozen.unsent <= 1
                    # the other seat is served at once
                    await asyncio.wait_for(_drive(a, 10), timeout=5)
                    await b.send(m.Stop())
                    ended = await b.wait_for(lambda x: isinstance(x, m.SessionEnded), timeout=30)
                finally:
                    with contextlib.suppress(ProcessLookupError):  # killed, as it should be
                        os.kill(frozen.pid, signal.SIGCONT)
                assert isinstance(ended, m.SessionEnded)
                assert ended.session_id == started.session_id
                assert ended.reason == "error"
                assert ended.detail.startswith(
                    "the session's process died (it did not end within 3 s of being asked "
                    "to stop, so the server killed it: killed by SIGKILL)"
                ), ended.detail
                await _drive(a, 5)
                assert all(not isinstance(x, m.SessionEnded) for x in a.received)
                assert (await _stop(a)).reason == "operator_stop"

            assert _recorded(server) == {
                "steady": [("interrupted", "operator_stop")],
                "frozen": [("interrupted", "crash_recovered")],
            }

    asyncio.run(scenario())


def test_a_dropped_operator_takes_back_its_own_seat(tmp_path: Path) -> None:
    async def scenario() -> None:
        with running_server(tmp_path, max_sessions=2, grace_s=10.0) as server:
            async with client(server) as a:
                await a.hello()
                await _start(a, "first")
                async with client(server) as b:
                    welcome = await b.hello()
                    assert welcome.seat == "2" and welcome.resume_token is not None
                    started = await _start(b, "second")
                    await _drive(b, 5)
                # b dropped: its seat is kept for it, so a newcomer finds the server full
                async with client(server) as newcomer:
                    assert (await newcomer.hello()).role == "spectator"
                async with client(server) as back:
                    again = await back.hello(token=welcome.resume_token)
                    assert (again.role, again.seat) == ("operator", "2")
                    assert again.session_id == started.session_id
                    await _drive(back, 5)
                    assert (await _stop(back)).reason == "operator_stop"
                await _stop(a)
            assert _recorded(server) == {
                "first": [("interrupted", "operator_stop")],
                "second": [("interrupted", "operator_stop")],
            }

    asyncio.run(scenario())


def test_one_seat_turns_a_second_operator_into_a_spectator_and_says_why(
    tmp_path: Path,
) -> None:
    async def scenario() -> None:
        with running_server(tmp_path) as server:
            async with client(server) as a, client(server) as b:
                assert (await a.hello()).role == "operator"
                assert (await b.hello()).role == "spectator"
                full = await b.wait_for(lambda x: isinstance(x, m.Error))
                assert isinstance(full, m.Error) and full.code == "server_full"
                assert "the one seat has an operator" in full.message
                await b.send(m.Hello(role="spectator", seat="9"))
                refused = await b.wait_for(lambda x: isinstance(x, m.Error))
                assert isinstance(refused, m.Error) and refused.code == "protocol"
            async with client(server) as c:
                await c.send(m.Hello(role="spectator", seat="9"))
                refused = await c.wait_for(lambda x: isinstance(x, m.Error))
                assert isinstance(refused, m.Error) and refused.code == "invalid_value"
                assert refused.message == "hello.seat = '9': no such seat; seats now: 1"
                assert (await c.hello("spectator", seat="1")).seat == "1"  # may try again
            # the one-seat server records straight into the store: no shards
            assert not shard_folder(server.options.store).exists()

    asyncio.run(scenario())


def test_shards_a_killed_server_left_are_merged_at_the_next_start(tmp_path: Path) -> None:
    async def scenario(store: Path) -> None:
        with running_server(tmp_path, store=store) as server:
            async with client(server) as a:
                await a.hello()
                await _start(a, "earlier")
                await _drive(a, 5)
                await _stop(a)
            del server

    donor = tmp_path / "donor.sqlite"
    asyncio.run(scenario(donor))
    store = tmp_path / "store.sqlite"
    folder = shard_folder(store)
    folder.mkdir()
    shutil.copy(donor, folder / "0123abcd.sqlite")
    (folder / "broken.sqlite").write_bytes(b"not a store")
    seats = Seats(ServerOptions(store=store, max_sessions=3))
    lines = seats.merge_leftovers()
    assert f"{folder / '0123abcd.sqlite'}: merged into {store}" in lines
    (kept,) = [line for line in lines if "broken" in line]
    assert kept.startswith(f"{folder / 'broken.sqlite'}: not merged (") and kept.endswith(
        "it stays for the next start"
    )
    assert len(lines) == 2
    assert not [p for p in folder.iterdir() if p.name.startswith("0123abcd")]  # merged: gone
    assert (folder / "broken.sqlite").read_bytes() == b"not a store"  # kept as it was
    assert verify_store(store) == []
    with Store.open(store, writer=False) as reader:
        assert [s.operator_id for s in reader.sessions()] == ["earlier"]


@pytest.mark.parametrize("sessions", [0, 65])
def test_the_number_of_sessions_is_checked(sessions: int) -> None:
    with pytest.raises(ConfigError, match=f"--sessions = {sessions}: must be 1 to 64"):
        ServerOptions(max_sessions=sessions)

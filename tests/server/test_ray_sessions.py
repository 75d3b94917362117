"""Sessions in Ray actors (``workcell serve --sessions N --ray local``): a real Ray on this
machine, started once for the module, real sockets. Operators drive sessions that run in
Ray workers, recorded into shards merged into a store that verifies; a killed actor ends
only its own session; an actor that cannot write the server's folder hands its shard back;
an address where no Ray answers is one clear error."""

from __future__ import annotations

import asyncio
import os
import time
from collections.abc import Iterator
from pathlib import Path

import pytest
import ray

from tests.server.harness import client, running_server
from tests.server.test_seats import _drive, _recorded, _start, _stop
from workcell.cli.main import main
from workcell.errors import ConfigError
from workcell.protocol import messages as m
from workcell.server.options import ServerOptions
from workcell.server.session_actor import RaySessions, SessionActor
from workcell.server.shards import shard_folder


@pytest.fixture(scope="module")
def ray_sessions() -> Iterator[RaySessions]:
    with RaySessions.connect("local", sessions=2) as sessions:
        yield sessions


def _actor(session: object) -> SessionActor:
    assert isinstance(session, SessionActor)
    assert session.pid is not None and session.pid != os.getpid()
    with open(f"/proc/{session.pid}/cmdline", "rb") as cmdline:
        assert cmdline.read().startswith(b"ray::SessionActorBody"), "not a Ray actor's worker"
    with open(f"/proc/{session.pid}/stat") as stat:
        assert int(stat.read().rsplit(")", 1)[1].split()[1]) != os.getpid(), "the server's child"
    return session


def _gone(session: SessionActor) -> bool:
    """The actor's worker has exited (Ray lets it go once the session is over; a generous
    budget, only a machine busy with other work needs it)."""
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline:
        try:
            with open(f"/proc/{session.pid}/cmdline", "rb") as cmdline:
                if not cmdline.read().startswith(b"ray::SessionActorBody"):
                    return True
        except (FileNotFoundError, ProcessLookupError):  # gone before the open, or the read
            return True
        time.sleep(0.1)
    return False


def test_two_operators_drive_sessions_in_ray_actors(
    tmp_path: Path, ray_sessions: RaySessions
) -> None:
    async def scenario() -> None:
        with running_server(tmp_path, max_sessions=2, ray="local", launch=ray_sessions) as server:
            async with client(server) as a, client(server) as b:
                await a.hello()
                await b.hello()
                started = [await _start(a, "left"), await _start(b, "right")]
                actors = [_actor(c.session) for c in server.seats.conductors.values()]
                assert len({s.pid for s in actors}) == 2
                assert all(s.placement and s.placement.in_place for s in actors)
                await asyncio.gather(_drive(a, 10), _drive(b, 10))
                sims = server.get_json("/api/diagnostics")["sims"]
                assert sorted(s["session_id"] for s in sims) == sorted(
                    s.session_id for s in started
                )
                assert all(s["steps"] > 0 for s in sims)  # pacing relayed from the actors
                ended = await asyncio.gather(_stop(a), _stop(b))
                assert [e.reason for e in ended] == ["operator_stop"] * 2
                assert all(e.detail == "" for e in ended)
            assert all(_gone(s) for s in actors)
        assert _recorded(server) == {
            "left": [("interrupted", "operator_stop")],
            "right": [("interrupted", "operator_stop")],
        }
        assert main(["verify", "--store", str(server.options.store)]) == 0
        assert list(shard_folder(server.options.store).glob("*")) == []

    asyncio.run(scenario())


def test_a_killed_actor_ends_only_its_own_session(
    tmp_path: Path, ray_sessions: RaySessions
) -> None:
    async def scenario() -> None:
        with running_server(tmp_path, max_sessions=2, ray="local", launch=ray_sessions) as server:
            async with client(server) as a, client(server) as b, client(server) as watcher:
                await a.hello()
                await b.hello()
                await _start(a, "steady")
                started = await _start(b, "doomed")
                await watcher.hello("spectator", seat="2")
                doomed = _actor(server.seats.conductors["2"].session)
                await _drive(b, 5)
                ray.kill(doomed.actor)
                ended = await b.wait_for(lambda x: isinstance(x, m.SessionEnded), timeout=30)
                assert isinstance(ended, m.SessionEnded)
                assert ended.session_id == started.session_id
                assert ended.reason == "error"
                assert ended.detail == (
                    "the session's Ray actor died (it was killed by `ray.kill`); its trial is "
                    "recorded up to the last frames written, and closed as interrupted "
                    "(crash_recovered)"
                )
                assert await watcher.wait_for(lambda x: isinstance(x, m.SessionEnded)) == ended

                # seat 1 never noticed: it still runs and records its operator's inputs
                await _drive(a, 10)
                assert not any(isinstance(x, m.SessionEnded) for x in a.received)
                assert (await _stop(a)).reason == "operator_stop"
        assert _recorded(server) == {
            "steady": [("interrupted", "operator_stop")],
            # left open by the killed actor, recovered when its shard was merged
            "doomed": [("interrupted", "crash_recovered")],
        }

    asyncio.run(scenario())


def test_actors_away_from_the_servers_folder_hand_their_shards_back(
    tmp_path: Path, ray_sessions: RaySessions
) -> None:
    away = RaySessions("local", hand_back=True)  # as on nodes without the shard folder

    async def scenario() -> None:
        with running_server(tmp_path, max_sessions=2, ray="local", launch=away) as server:
            async with client(server) as a, client(server) as b:
                await a.hello()
                await b.hello()
                await _start(a, "remote")
                await _start(b, "lost")
                actors = [_actor(c.session) for c in server.seats.conductors.values()]
                assert all(s.placement and not s.placement.in_place for s in actors)
                assert list(shard_folder(server.options.store).glob("*.sqlite")) == []
                await asyncio.gather(_drive(a, 10), _drive(b, 5))
                lost = actors[1].placement
                assert lost is not None
                ray.kill(actors[1].actor)
                ended = await b.wait_for(lambda x: isinstance(x, m.SessionEnded), timeout=30)
                assert isinstance(ended, m.SessionEnded) and ended.reason == "error"
                assert ended.detail == (
                    "the session's Ray actor died (it was killed by `ray.kill`); its record "
                    f"was kept on the actor's node ({lost.node}) until the "
                    "session's end, and is lost"
                )
                assert (await _stop(a)).reason == "operator_stop"
        # the shard handed back was merged; the killed actor's record never reached here
        assert _recorded(server) == {"remote": [("interrupted", "operator_stop")]}
        assert list(shard_folder(server.options.store).glob("*")) == []

    asyncio.run(scenario())


def test_a_ray_that_does_not_answer_is_one_clear_error(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    store = tmp_path / "store.sqlite"
    args = ["serve", "--store", str(store), "--port", "0", "--sessions", "2"]
    assert main([*args, "--ray", "127.0.0.1:9"]) == 2
    error = capsys.readouterr().err
    assert error.startswith("workcell: error: cannot connect to Ray at '127.0.0.1:9': nothing ")
    assert error.count("\n") == 1
    assert not store.exists() and not shard_folder(store).exists()


def test_ray_needs_several_seats() -> None:
    with pytest.raises(ConfigError, match=r"--ray = local: .* give --sessions 2 or more"):
        ServerOptions(ray="local")
    assert ServerOptions(ray="local", max_sessions=2).ray == "local"

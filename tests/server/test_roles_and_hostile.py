"""Spectators watch but cannot drive; hostile messages are refused and nothing else stops."""

from __future__ import annotations

import asyncio
import json
from pathlib import Path

from tests.server.harness import FAST_SETTINGS, client, hand, running_server
from workcell.protocol import messages as m
from workcell.record.store import Store


def test_a_spectator_receives_state_but_cannot_control(tmp_path: Path) -> None:
    async def scenario() -> None:
        with running_server(tmp_path) as server:
            async with client(server) as operator, client(server) as second:
                assert (await operator.hello()).role == "operator"
                welcome = await second.hello("operator")  # the seat is taken
                assert welcome.role == "spectator" and welcome.resume_token is None
                await operator.send(m.StartSession(settings=FAST_SETTINGS))
                started = await second.wait_for(lambda x: isinstance(x, m.SessionStarted))
                assert isinstance(started, m.SessionStarted)
                state = await second.wait_for(lambda x: isinstance(x, m.State))
                assert isinstance(state, m.State) and state.hud is not None
                for attempt in (
                    m.Stop(),
                    m.StartSession(settings={}),
                    m.Input(1, 0.0, "desktop", None, hand(stick=(0, 1)), hand()),
                ):
                    await second.send(attempt)
                    error = await second.wait_for(lambda x: isinstance(x, m.Error))
                    assert isinstance(error, m.Error) and error.code == "not_allowed"
                assert server.conductor.session is not None  # still running
                await operator.send(m.Stop())
                await second.wait_for(lambda x: isinstance(x, m.SessionEnded))

    asyncio.run(scenario())


HOSTILE: list[str | bytes] = [
    "not json",
    b"\x00\xff binary",
    '{"type":"input"}',
    '{"type":"ping","t_client":NaN}',
    '{"type":"ping","t_client":1,"rtt_ms":-5}',
    '{"type":"ping","t_client":1,"rtt_ms":"fast"}',
    '{"type":"start_session","settings":{},"consent":"yes"}',
    json.dumps({"type": "hello", "role": "operator", "nonsense": 1}),
    '{"type":"input","seq":99,"t_client":0,"source":"xr","headset":[0,1,0,5,5,5,5],'
    '"left":{"pose":null,"grip":0,"trigger":0,"stick":[0,0],"buttons":0},'
    '"right":{"pose":null,"grip":0,"trigger":0,"stick":[0,0],"buttons":0}}',
    '{"type":"start_session","settings":{"a":"' + "x" * 70_000 + '"}}',
    "[" * 10_000 + "]" * 10_000,
    '{"type":"ping","t_client":1' + "0" * 400 + "}",  # too large for a float
    '{"type":"start_session","settings":{"task":{"time_limit_s":-1' + "0" * 400 + "}}}",
    # lone surrogates: JSON escapes them, Python decodes them, UTF-8 (the store, the
    # encoder) has no form for them
    '{"type":"stop","reason":"\\ud800 my words"}',
    '{"type":"start_session","settings":{"\\udfff":1}}',
    '{"type":"ping","t_client":"\\ud83d"}',
]


def test_hostile_messages_get_errors_and_the_session_carries_on(tmp_path: Path) -> None:
    async def scenario() -> None:
        with running_server(tmp_path) as server:
            async with client(server) as operator, client(server) as watcher:
                await operator.hello()
                await watcher.hello("spectator")
                await operator.send(m.StartSession(settings=FAST_SETTINGS))
                await operator.wait_for(lambda x: isinstance(x, m.SessionStarted))
                codes = []
                for raw in HOSTILE:
                    await operator.send_raw(raw)
                    error = await operator.wait_for(lambda x: isinstance(x, m.Error))
                    assert isinstance(error, m.Error) and not error.fatal
                    codes.append(error.code)
                assert set(codes) == {"malformed", "invalid_value", "too_large"}
                # out of order: an input older than the last one
                await operator.input()
                await operator.input()
                operator.seq = 0
                await operator.input()
                error = await operator.wait_for(lambda x: isinstance(x, m.Error))
                assert isinstance(error, m.Error) and error.code == "protocol"
                await operator.send(m.Hello(role="operator"))  # a second hello
                error = await operator.wait_for(lambda x: isinstance(x, m.Error))
                assert isinstance(error, m.Error) and error.code == "protocol"
                # the simulation, the other client and this connection carry on
                before = await watcher.wait_for(lambda x: isinstance(x, m.State))
                await asyncio.sleep(0.3)
                after = await watcher.wait_for(lambda x: isinstance(x, m.State))
                assert isinstance(before, m.State) and isinstance(after, m.State)
                assert after.t_sim > before.t_sim
                await operator.send(m.Ping(t_client=1.0))
                await operator.wait_for(lambda x: isinstance(x, m.Pong))
                stats = server.get_json("/api/diagnostics")
                mine = next(c for c in stats["clients"] if c["role"] == "operator")
                assert sum(mine["errors"].values()) == len(HOSTILE) + 2
                await operator.send(m.Stop())
                await operator.wait_for(lambda x: isinstance(x, m.SessionEnded))
            with Store.open(server.options.store, writer=False) as store:
                (trial,) = store.trials()
                assert trial.n_frames is not None and trial.n_frames > 5

    asyncio.run(scenario())


def test_a_flood_is_rate_limited(tmp_path: Path) -> None:
    async def scenario() -> None:
        with running_server(tmp_path, max_messages_per_s=100.0, burst=20) as server:
            async with client(server) as flooder, client(server) as other:
                await flooder.hello("spectator")
                await other.hello("spectator")
                for _ in range(400):
                    await flooder.send(m.Ping(t_client=0.0))
                error = await flooder.wait_for(lambda x: isinstance(x, m.Error), timeout=10)
                assert isinstance(error, m.Error) and error.code == "rate_limited"
                await other.send(m.Ping(t_client=2.0))
                pong = await other.wait_for(lambda x: isinstance(x, m.Pong))
                assert isinstance(pong, m.Pong) and pong.t_client == 2.0
                stats = server.get_json("/api/diagnostics")
                counts = {c["client"]: c["errors"].get("rate_limited", 0) for c in stats["clients"]}
                assert max(counts.values()) > 300 and min(counts.values()) == 0

    asyncio.run(scenario())


def test_inputs_well_within_the_rate_while_a_session_starts_are_not_rate_limited(
    tmp_path: Path,
) -> None:
    """The operator drives on at a normal rate while its session starts (which takes a
    process start, far longer than the burst lasts at this rate)."""

    async def scenario() -> None:
        with running_server(tmp_path, max_messages_per_s=100.0, burst=10) as server:
            async with client(server) as operator:
                await operator.hello()
                await operator.send(m.StartSession(settings=FAST_SETTINGS))

                async def drive() -> None:
                    while True:
                        await operator.input()
                        await asyncio.sleep(1 / 40)

                driver = asyncio.create_task(drive())
                try:
                    await operator.wait_for(lambda x: isinstance(x, m.SessionStarted), 30)
                    await asyncio.sleep(0.5)
                finally:
                    driver.cancel()
                await operator.send(m.Stop())
                await operator.wait_for(lambda x: isinstance(x, m.SessionEnded))
                refused = [x for x in operator.received if isinstance(x, m.Error)]
                assert refused == []
                stats = server.get_json("/api/diagnostics")
                assert all(c["errors"] == {} for c in stats["clients"])

    asyncio.run(scenario())


def test_a_stop_sent_right_after_start_session_stops_the_session_it_started(
    tmp_path: Path,
) -> None:
    async def scenario() -> None:
        with running_server(tmp_path) as server:
            async with client(server) as operator:
                await operator.hello()
                await operator.send(m.StartSession(settings=FAST_SETTINGS))
                await operator.send(m.Stop())
                await operator.wait_for(lambda x: isinstance(x, m.SessionEnded), 30)
                assert any(isinstance(x, m.SessionStarted) for x in operator.received)
                assert not any(isinstance(x, m.Error) for x in operator.received)

    asyncio.run(scenario())


def test_messages_before_hello_are_refused(tmp_path: Path) -> None:
    async def scenario() -> None:
        with running_server(tmp_path) as server:
            async with client(server) as c:
                await c.send(m.Stop())
                error = await c.wait_for(lambda x: isinstance(x, m.Error))
                assert isinstance(error, m.Error) and "send hello first" in error.message

    asyncio.run(scenario())

"""``workcell serve --study``: invites, a participant's plan run over real sockets, consent,
what an invite opens and what it does not, the admin's overview and stop, capacity, and
resuming after a server restart."""

from __future__ import annotations

import asyncio
import hashlib
import json
import os
import signal
import socket
import stat
import subprocess
import sys
import time
import urllib.error
import urllib.request
from pathlib import Path
from typing import Any

import pytest

from tests.server.harness import Client, RunningServer, client, running_server
from workcell.errors import ConfigError
from workcell.protocol import messages as m
from workcell.record.store import Store
from workcell.record.verify import verify_store
from workcell.study.config import Condition, Step, StudyConfig
from workcell.study.invites import invites_path, load_or_create
from workcell.study.plan import participant_plan
from workcell.study.template import TEMPLATE

CONSENT = "I agree that my teleoperation is recorded."


def study(time_limit_s: float = 0.5, participants: int = 2) -> StudyConfig:
    """Two conditions, one practice session in each: a participant's plan is two sessions,
    each one trial that times out after ``time_limit_s``."""
    return StudyConfig(
        name="pilot",
        participants=participants,
        instructions="Move the box to the green zone.",
        consent=CONSENT,
        session={"task": {"countdown_s": 0.0, "time_limit_s": time_limit_s}},
        conditions=(
            Condition("assisted", {"world.grasp": "assisted"}),
            Condition("physical", {"world.grasp": "physical"}),
        ),
        steps=(Step("practice", 1),),
    )


def token_of(server: RunningServer, participant: str) -> str:
    desk = server.seats.desk
    assert desk is not None
    return desk.invites.participants[participant]


def get_as(server: RunningServer, path: str, token: str, method: str = "GET") -> tuple[int, Any]:
    status, body = server.get(path, {"Authorization": f"Bearer {token}"}, method)
    try:
        return status, json.loads(body)
    except ValueError:
        return status, body.decode()


async def start(participant: Client, consent: bool = False, **settings: Any) -> m.ServerMessage:
    await participant.send(m.StartSession(settings=dict(settings), consent=consent))
    return await participant.wait_for(lambda x: isinstance(x, m.SessionStarted | m.Error))


async def ended(participant: Client) -> m.SessionEnded:
    message = await participant.wait_for(lambda x: isinstance(x, m.SessionEnded), timeout=30)
    assert isinstance(message, m.SessionEnded)
    return message


def test_a_participant_runs_their_plan_with_consent_once(tmp_path: Path) -> None:
    config = study()
    plan = participant_plan(config, "p01")
    digest = hashlib.sha256(CONSENT.encode()).hexdigest()

    async def scenario(server: RunningServer) -> None:
        token = token_of(server, "p01")
        status, me = get_as(server, "/api/study/me", token)
        assert status == 200
        assert (me["participant"], me["done"], me["total"], me["consented"]) == ("p01", 0, 2, False)
        assert me["instructions"] == config.instructions and me["consent"] == CONSENT
        assert me["next"]["condition"] == plan[0].condition and me["next"]["mode"] == "practice"
        async with client(server, query=f"?token={token}") as p01:
            welcome = await p01.hello("operator")
            assert (welcome.role, welcome.seat) == ("operator", "p01")
            refused = await start(p01)
            assert isinstance(refused, m.Error) and "consent" in refused.message
            # the browser's settings do not count: the plan's do
            started = await start(p01, consent=True, operator_id="mallory", seed=7)
            assert isinstance(started, m.SessionStarted), started
            assert started.operator_id == "p01"
            assert started.settings["condition"] == plan[0].condition
            assert started.settings["seed"] == plan[0].config.seed
            assert started.settings["consent"] == digest
            assert (await ended(p01)).reason == "completed"
            status, me = get_as(server, "/api/study/me", token)
            assert (me["done"], me["consented"]) == (1, True)
            assert me["next"]["condition"] == plan[1].condition
            started = await start(p01)  # consent was given once: not asked again
            assert isinstance(started, m.SessionStarted), started
            assert started.settings["condition"] == plan[1].condition
            assert (await ended(p01)).reason == "completed"
            refused = await start(p01, consent=True)
            assert isinstance(refused, m.Error) and "every session" in refused.message
        status, me = get_as(server, "/api/study/me", token)
        assert (me["done"], me["next"]) == (2, None)

    with running_server(tmp_path, study=config) as server:
        asyncio.run(scenario(server))
    store = tmp_path / "store.sqlite"
    assert verify_store(store) == []
    with Store.open(store, writer=False) as reader:
        sessions = reader.sessions()
        trials = reader.trials()
    assert [(s.operator_id, s.parameters["condition"], s.status) for s in sessions] == [
        ("p01", plan[0].condition, "completed"),
        ("p01", plan[1].condition, "completed"),
    ]
    assert {t.session_id for t in trials} == {s.session_id for s in sessions}


def test_an_invite_opens_only_the_participants_own_page_and_session(tmp_path: Path) -> None:
    async def scenario(server: RunningServer) -> None:
        p01 = token_of(server, "p01")
        assert server.get("/")[0] == 401  # a study server always needs a token
        assert get_as(server, "/?token=nonsense-token", "nonsense-token")[0] == 401
        assert get_as(server, "/", p01)[0] == 200
        assert get_as(server, "/api/defaults", p01)[0] == 200
        for path in ("/api/sessions", "/api/diagnostics", "/api/study", "/api/trials/x/frames"):
            status, body = get_as(server, path, p01)
            assert status == 403 and "admin" in body, path
        admin = server.options.token
        assert admin is not None
        assert get_as(server, "/api/sessions", admin)[0] == 200
        async with client(server, query=f"?token={p01}") as spy:
            await spy.send(m.Hello(role="spectator", resume_token=None, seat="p02"))
            error = await spy.wait_for(lambda x: isinstance(x, m.Error))
            assert isinstance(error, m.Error) and error.code == "not_allowed"
            assert "only your own seat, p01" in error.message
        async with client(server, query=f"?token={p01}") as driver:
            assert (await driver.hello("operator")).role == "operator"
            async with client(server, query=f"?token={p01}") as second_tab:
                welcome = await second_tab.hello("operator")
                assert (welcome.role, welcome.seat) == ("spectator", "p01")
                error = await second_tab.wait_for(lambda x: isinstance(x, m.Error))
                assert isinstance(error, m.Error) and "another connection" in error.message

    with running_server(tmp_path, study=study()) as server:
        asyncio.run(scenario(server))


def test_the_admin_sees_every_participant_live_and_stops_a_session(tmp_path: Path) -> None:
    async def scenario(server: RunningServer) -> None:
        admin = server.options.token
        assert admin is not None
        p01 = token_of(server, "p01")
        status, overview = get_as(server, "/api/study", admin)
        assert status == 200 and overview["max_sessions"] == 2
        assert [r["state"] for r in overview["participants"]] == ["offline", "offline"]
        assert overview["participants"][1]["invite"] == f"/?token={token_of(server, 'p02')}"
        async with client(server, query=f"?token={p01}") as participant:
            await participant.hello("operator")
            await participant.send(m.Ping(t_client=0.5))  # no round trip measured yet
            assert isinstance(await participant.wait_for(lambda x: isinstance(x, m.Pong)), m.Pong)
            await participant.send(m.Ping(t_client=1.0, rtt_ms=12.5))
            started = await start(participant, consent=True)
            assert isinstance(started, m.SessionStarted)
            row = get_as(server, "/api/study", admin)[1]["participants"][0]
            assert (row["participant"], row["state"], row["done"]) == ("p01", "running", 0)
            assert row["condition"] == started.settings["condition"]
            assert row["session_id"] == started.session_id and row["rtt_ms"] == 12.5
            assert get_as(server, "/api/study/participants/p01/stop", p01, "POST")[0] == 403
            assert get_as(server, "/api/study/participants/p99/stop", admin, "POST")[0] == 404
            status, _ = get_as(server, "/api/study/participants/p01/stop", admin, "POST")
            assert status == 200
            assert (await ended(participant)).reason == "admin_stop"
            status, body = get_as(server, "/api/study/participants/p01/stop", admin, "POST")
            assert status == 409 and "no session is running" in body["error"]
            row = get_as(server, "/api/study", admin)[1]["participants"][0]
            assert (row["state"], row["done"], row["trials"], row["successes"]) == (
                "waiting",
                0,
                1,
                0,
            )

    with running_server(tmp_path, study=study(time_limit_s=60.0), max_sessions=2) as server:
        asyncio.run(scenario(server))
    with Store.open(tmp_path / "store.sqlite", writer=False) as reader:
        (trial,) = reader.trials()
    assert (trial.outcome, trial.interruption_reason) == ("interrupted", "admin_stop")


def test_a_full_server_says_so_and_a_restart_resumes_each_plan(tmp_path: Path) -> None:
    config = study()

    async def first_run(server: RunningServer) -> None:
        async with (
            client(server, query=f"?token={token_of(server, 'p01')}") as p01,
            client(server, query=f"?token={token_of(server, 'p02')}") as p02,
        ):
            await p01.hello("operator")
            await p02.hello("operator")
            assert isinstance(await start(p01, consent=True), m.SessionStarted)
            full = await start(p02, consent=True)
            assert isinstance(full, m.Error) and full.code == "server_full"
            assert "--sessions 1" in full.message
            assert (await ended(p01)).reason == "completed"

    with running_server(tmp_path, study=config) as server:
        tokens = dict(server.seats.desk.invites.participants) if server.seats.desk else {}
        asyncio.run(first_run(server))

    path = invites_path(tmp_path / "store.sqlite", config)
    assert stat.S_IMODE(os.stat(path).st_mode) == 0o600

    async def second_run(server: RunningServer) -> None:
        status, me = get_as(server, "/api/study/me", tokens["p01"])  # the same invite works
        assert (status, me["done"], me["consented"]) == (200, 1, True)
        assert me["next"]["position"] == 2

    with running_server(tmp_path, study=config) as server:
        assert server.seats.desk is not None
        assert dict(server.seats.desk.invites.participants) == tokens
        asyncio.run(second_run(server))


def test_invites_survive_a_grown_study_and_refuse_another_studys_file(tmp_path: Path) -> None:
    store = tmp_path / "store.sqlite"
    small = study(participants=2)
    first = load_or_create(invites_path(store, small), small)
    grown = study(participants=3)
    again = load_or_create(invites_path(store, grown), grown)
    assert again.admin == first.admin
    assert {k: again.participants[k] for k in first.participants} == dict(first.participants)
    assert set(again.participants) == {"p01", "p02", "p03"}
    assert len(set(again.participants.values()) | {again.admin}) == 4
    other = StudyConfig(name="other")
    path = invites_path(store, small)
    path.replace(invites_path(store, other))
    with pytest.raises(ConfigError, match="holds the invites of study 'pilot', not 'other'"):
        load_or_create(invites_path(store, other), other)


def test_serve_study_prints_an_invite_per_participant_and_the_admin_link(tmp_path: Path) -> None:
    study_file = tmp_path / "pilot.toml"
    pilot = TEMPLATE.replace('name = "study"', 'name = "pilot"')
    study_file.write_text(pilot.replace("participants = 12", "participants = 2"), "utf-8")
    store = tmp_path / "store.sqlite"
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = int(s.getsockname()[1])
    command = [sys.executable, "-m", "workcell", "serve", "--store", str(store)]
    process = subprocess.Popen(
        [*command, "--port", str(port), "--study", str(study_file)],
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
        env={**os.environ, "MUJOCO_GL": "egl"},
    )
    try:
        assert process.stdout is not None
        lines = [process.stdout.readline() for _ in range(5)]
        assert lines[0].startswith("study pilot: 2 participants, 4 sessions each"), lines
        invites = load_or_create(invites_path(store, StudyConfig(name="pilot")), study())
        base = f"http://127.0.0.1:{port}"
        assert f"admin page  {base}/?token={invites.admin}&role=spectator#/admin" in lines[1]
        assert f"p01         {base}/?token={invites.participants['p01']}" in lines[2]
        assert f"p02         {base}/?token={invites.participants['p02']}" in lines[3]
        # the last line opens the admin page, not a Setup page that would record strays
        assert (
            lines[4]
            == f"workcell serve: open {base}/?token={invites.admin}&role=spectator#/admin\n"
        )
        request = f"{base}/api/study/me?token={invites.participants['p02']}"
        assert json.loads(_get_when_up(request))["participant"] == "p02"
    finally:
        process.send_signal(signal.SIGTERM)
        process.communicate(timeout=30)
    study_file.write_text(pilot.replace('order = "latin_square"', 'order = "random"'), "utf-8")
    failed = subprocess.run(
        [*command, "--study", str(study_file)], capture_output=True, text=True, check=False
    )
    assert failed.returncode == 2
    assert "order" in failed.stderr and "latin_square" in failed.stderr


def _get_when_up(url: str, timeout: float = 20.0) -> bytes:
    """The body of ``url`` once the server listens (it prints its links just before)."""
    deadline = time.monotonic() + timeout
    while True:
        try:
            with urllib.request.urlopen(url, timeout=10) as response:
                return bytes(response.read())
        except urllib.error.URLError:
            if time.monotonic() > deadline:
                raise
            time.sleep(0.1)


def test_an_unreadable_store_refuses_a_start_and_frees_the_seat(tmp_path: Path) -> None:
    (tmp_path / "store.sqlite").write_bytes(b"not a database" * 100)

    async def scenario(server: RunningServer) -> None:
        async with client(server, query=f"?token={token_of(server, 'p01')}") as p01:
            await p01.hello("operator")
            for _ in range(2):  # the second start is refused the same way: nothing is stuck
                refused = await start(p01, consent=True)
                assert isinstance(refused, m.Error) and refused.code == "not_allowed"
                assert refused.message.startswith("start_session: ")
                assert "store.sqlite" in refused.message
        assert server.seats.running == 0

    with running_server(tmp_path, study=study()) as server:
        asyncio.run(scenario(server))

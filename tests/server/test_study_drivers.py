"""Many correctors (issue 35): a study condition sets the driver, so that several
participants watch and correct the expert at the same time, each in their own session on
``workcell serve --study``; the record names each participant in their take-overs and the
driver in every trial. A condition's bad driver is named where it is."""

from __future__ import annotations

import asyncio
import tomllib
from pathlib import Path

import pytest

from tests.server.harness import Client, RunningServer, client, running_server
from tests.server.test_study_server import token_of
from workcell.errors import ConfigError
from workcell.protocol import messages as m
from workcell.record.store import Store
from workcell.study.config import Condition, Step, StudyConfig, study_from_mapping
from workcell.study.plan import participant_plan
from workcell.study.template import TEMPLATE
from workcell.task import events as ev


def test_a_condition_sets_the_driver_and_a_bad_one_is_named() -> None:
    data = tomllib.loads(TEMPLATE)
    data["conditions"][0]["settings"] = {"driver": "expert"}
    data["conditions"][1]["settings"] = {}
    study = study_from_mapping(data)
    drivers = {p.condition: p.config.driver for p in participant_plan(study, "p01")}
    assert drivers == {"assisted": "expert", "physical": "person"}
    data["conditions"][1]["settings"] = {"driver": "autopilot"}
    with pytest.raises(ConfigError) as raised:
        study_from_mapping(data)
    (line,) = raised.value.problems
    assert line.startswith("conditions[2].settings.driver = 'autopilot'")
    assert "person, expert or policy:PATH" in line


STUDY = StudyConfig(
    name="corrections",
    participants=2,
    instructions="Watch the robot; take over when it goes wrong.",
    session={"task": {"countdown_s": 0.0, "time_limit_s": 4.0}},
    conditions=(
        Condition("expert_assisted", {"driver": "expert"}),
        Condition("expert_physical", {"driver": "expert", "world.grasp": "physical"}),
    ),
    steps=(Step("practice", 1),),
)


async def correct_once(participant: Client, reason: str) -> None:
    """Start the planned session, take over, hand back, and wait for its end."""
    await participant.hello("operator")
    await participant.send(m.StartSession(settings={}, consent=False))
    started = await participant.wait_for(
        lambda x: isinstance(x, m.SessionStarted | m.Error | m.Queued | m.ConfigRejected), 30
    )
    assert isinstance(started, m.SessionStarted), started
    assert started.settings["driver"] == "expert"
    await participant.wait_for(lambda x: isinstance(x, m.State) and x.t_sim > 0.5, 30)
    await participant.send(m.TakeOver(reason=reason))
    await participant.wait_for(lambda x: isinstance(x, ev.TookOver), 15)
    await asyncio.sleep(0.5)
    await participant.send(m.HandBack())
    await participant.wait_for(lambda x: isinstance(x, ev.HandedBack), 15)
    ended = await participant.wait_for(lambda x: isinstance(x, m.SessionEnded), 60)
    assert isinstance(ended, m.SessionEnded) and ended.reason == "completed"


def test_two_participants_correct_the_expert_at_the_same_time(tmp_path: Path) -> None:
    async def scenario(server: RunningServer) -> None:
        tokens = [token_of(server, p) for p in ("p01", "p02")]
        async with (
            client(server, query=f"?token={tokens[0]}") as p01,
            client(server, query=f"?token={tokens[1]}") as p02,
        ):
            await asyncio.gather(correct_once(p01, "p01 here"), correct_once(p02, "p02 here"))

    with running_server(tmp_path, study=STUDY, max_sessions=2) as server:
        asyncio.run(scenario(server))
    with Store.open(tmp_path / "store.sqlite", writer=False) as reader:
        sessions = {s.session_id: s for s in reader.sessions()}
        trials = reader.trials()
        took = {
            e.payload["operator_id"]: e.payload for e in reader.events() if e.kind == "take_over"
        }
    assert sorted(s.operator_id for s in sessions.values()) == ["p01", "p02"]
    assert {t.driver for t in trials} == {"expert"} and len(trials) == 2
    assert set(took) == {"p01", "p02"}
    for participant, payload in took.items():
        assert (payload["driver"], payload["reason"]) == ("expert", f"{participant} here")
    conditions = {s.parameters["condition"] for s in sessions.values()}
    assert conditions == {"expert_assisted", "expert_physical"}  # the two orders, at once

"""The read-only JSON API over HTTP: defaults, sessions and replay frames."""

from __future__ import annotations

import asyncio
import json
from pathlib import Path

from tests.server.harness import FAST_SETTINGS, body_index, client, hand, running_server
from workcell.protocol import messages as m
from workcell.protocol.api import Defaults, SessionList, TrialReplay
from workcell.protocol.validation import build
from workcell.record.store import Store


def test_defaults_describe_every_setting(tmp_path: Path) -> None:
    with running_server(tmp_path) as server:
        defaults = build(Defaults, server.get_json("/api/defaults"), "defaults")
    assert isinstance(defaults, Defaults)
    by_key = {f.key: f for f in defaults.fields}
    mode = by_key["task.mode"]
    assert mode.kind == "choice" and mode.choices == ("practice", "collection", "challenge")
    assert mode.default == "practice" and "practice" in mode.doc
    kind = by_key["task.kind"]  # the tasks are offered as a choice of the built-in ones
    assert kind.kind == "choice" and kind.choices is not None
    assert kind.choices[0] == "box_transfer" and {"sort", "shelve"} <= set(kind.choices)
    assert kind.default == "box_transfer" and "module:Class" in kind.doc
    assert by_key["task.level_boxes"].kind == "int_list"
    assert by_key["task.level_boxes"].default == [1, 2, 3]
    assert by_key["recording.grip_threshold"].kind == "float"
    assert by_key["operator_id"].kind == "text"
    assert {"task", "recording", "world", "world.robot"} <= {s.key for s in defaults.sections}
    assert defaults.settings["seed"] == 0
    task = defaults.settings["task"]
    assert isinstance(task, dict) and task["rounds"] == 5


def test_sessions_and_replay_frames(tmp_path: Path) -> None:
    async def record() -> m.Scene:
        async with client(server) as c:
            await c.hello()
            await c.send(m.StartSession(settings=FAST_SETTINGS))
            scene = await c.wait_for(lambda x: isinstance(x, m.Scene) and len(x.bodies) > 0)
            await c.wait_for(lambda x: isinstance(x, m.SessionStarted))
            for _ in range(20):
                await c.input(left=hand(stick=(0.0, 1.0)))
                await asyncio.sleep(0.025)
            await c.send(m.Stop())
            await c.wait_for(lambda x: isinstance(x, m.SessionEnded))
            assert isinstance(scene, m.Scene)
            return scene

    with running_server(tmp_path) as server:
        assert server.get_json("/api/sessions") == {"sessions": []}
        live_scene = asyncio.run(record())
        listing = build(SessionList, server.get_json("/api/sessions"), "sessions")
        assert isinstance(listing, SessionList)
        (session,) = listing.sessions
        (trial,) = session.trials
        assert session.status == "interrupted" and session.mode == "practice"
        assert trial.outcome == "interrupted" and trial.interruption_reason == "operator_stop"
        assert trial.n_frames is not None and trial.n_frames >= 5
        replay = build(
            TrialReplay, server.get_json(f"/api/trials/{trial.trial_id}/frames?every=2"), "r"
        )
        assert isinstance(replay, TrialReplay)
        assert replay.every == 2 and len(replay.poses) == len(replay.t_sim)
        assert len(replay.poses) == (trial.n_frames + 1) // 2
        base = body_index(replay.scene, "base")
        assert body_index(live_scene, "base") == base
        assert len(replay.poses[0]) == sum(b.dynamic for b in replay.scene.bodies)
        first, last = replay.poses[0][base], replay.poses[-1][base]
        assert abs(last[0] - first[0]) + abs(last[1] - first[1]) > 0.05  # it drove
        assert replay.t_sim[0] == 0.0 and list(replay.t_sim) == sorted(replay.t_sim)
        assert server.get("/api/trials/nope/frames")[0] == 404
        assert server.get(f"/api/trials/{trial.trial_id}/frames?every=0")[0] == 400
        assert server.get(f"/api/trials/{trial.trial_id}/frames?every=x")[0] == 400


def test_setting_hints_are_generated_from_the_declarations(tmp_path: Path) -> None:
    with running_server(tmp_path) as server:
        hints = server.get_json("/api/settings/hints")["hints"]
        defaults = build(Defaults, server.get_json("/api/defaults"), "defaults")
    assert isinstance(defaults, Defaults)
    assert [h["key"] for h in hints] == [f.key for f in defaults.fields]
    by_key = {h["key"]: h for h in hints}
    assert by_key["world.conveyor.speed"] == {
        "key": "world.conveyor.speed",
        "unit": "m/s",
        "allowed": "between 0.01 and 1 m/s",
        "low": 0.01,
        "high": 1.0,
        "low_open": False,
        "whole": False,
    }
    assert by_key["task.mode"]["allowed"] == "one of 'practice', 'collection', 'challenge'"


def test_every_query_and_path_parameter_is_checked_into_one_clear_error(tmp_path: Path) -> None:
    """No parameter a route reads answers 500: a superscript digit (``int`` refuses it),
    5,000 digits (``int`` refuses those too), digits of another script; a path parameter
    of any length is named, cut short, in the 404."""
    with Store.open(tmp_path / "store.sqlite", writer=True):
        pass  # an empty store: the trial is looked for
    with running_server(tmp_path) as server:
        allowed = "must be a whole number 1 to 10000"
        for every, named in (
            ("%C2%B2", "'²'"),  # superscript two
            ("1" * 5000, "'11111111111111111111'... (5000 characters)"),
            ("%D9%A3", "'٣'"),  # Arabic-Indic three
            ("%FF", "'\ufffd'"),  # not UTF-8: the replacement character
            ("", "''"),
            ("1e3", "'1e3'"),
            ("10001", "'10001'"),
        ):
            status, body = server.get(f"/api/trials/t1/frames?every={every}")
            assert (status, json.loads(body)) == (400, {"error": f"every = {named}: {allowed}"})
        assert server.get("/api/trials/t1/frames?every=10000")[0] == 404  # in range: looked for
        status, body = server.get(f"/api/trials/{'a' * 5000}/frames")
        assert (status, json.loads(body)) == (
            404,
            {"error": f"trial {'a' * 64!r} is not in the store"},
        )

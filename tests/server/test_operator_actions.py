"""Operator actions besides driving (the in-VR menu, the desktop toolbar), over a real
socket: each is recorded as an event of the trial under way; restart_trial ends the running
trial (interrupted: operator_restart) and begins a new one; only the operator may act."""

from __future__ import annotations

import asyncio
from pathlib import Path

from tests.server.harness import FAST_SETTINGS, client, running_server
from workcell.protocol import messages as m
from workcell.record.store import Store
from workcell.task import events as ev


def test_actions_are_recorded_and_restart_begins_a_new_trial(tmp_path: Path) -> None:
    async def scenario() -> None:
        with running_server(tmp_path) as server:
            async with client(server) as operator, client(server) as spectator:
                await operator.hello()
                await spectator.hello(role="spectator")
                await operator.send(m.Act(action="restart_trial", source="xr_menu"))
                refused = await operator.wait_for(lambda x: isinstance(x, m.Error))
                assert isinstance(refused, m.Error) and refused.code == "not_allowed"
                assert "no session is running" in refused.message

                await operator.send(m.StartSession(settings=FAST_SETTINGS))
                await operator.wait_for(lambda x: isinstance(x, m.State))
                await spectator.send(m.Act(action="restart_trial", source="desktop"))
                refused = await spectator.wait_for(lambda x: isinstance(x, m.Error))
                assert isinstance(refused, m.Error) and refused.code == "not_allowed"

                await operator.send(m.Act(action="recenter_view", source="xr_menu"))
                await operator.send(m.Act(action="view_third", source="xr_button"))
                await asyncio.sleep(0.2)
                await operator.send(m.Act(action="restart_trial", source="xr_menu"))
                started = await operator.wait_for(
                    lambda x: isinstance(x, ev.TrialStarted) and x.trial_index == 1
                )
                assert isinstance(started, ev.TrialStarted)
                await operator.send(m.Act(action="view_first", source="desktop"))
                await asyncio.sleep(0.2)
                await operator.send(m.Stop())
                ended = await operator.wait_for(lambda x: isinstance(x, m.SessionEnded))
                assert isinstance(ended, m.SessionEnded)
                assert ended.reason == "operator_stop" and ended.trials == 2
            with Store.open(server.options.store, writer=False) as store:
                first, second = store.trials()
                assert (first.trial_index, first.outcome) == (0, "interrupted")
                assert first.interruption_reason == "operator_restart"
                assert (second.trial_index, second.outcome) == (1, "interrupted")
                assert second.interruption_reason == "operator_stop"
                acted = [
                    (e.trial_id, e.payload["action"], e.payload["source"])
                    for e in store.events(session_id=first.session_id)
                    if e.kind == "operator_action"
                ]
                assert acted == [
                    (first.trial_id, "recenter_view", "xr_menu"),
                    (first.trial_id, "view_third", "xr_button"),
                    (first.trial_id, "restart_trial", "xr_menu"),
                    (second.trial_id, "view_first", "desktop"),
                ]

    asyncio.run(scenario())


def test_an_unknown_action_is_one_clear_error(tmp_path: Path) -> None:
    async def scenario() -> None:
        with running_server(tmp_path) as server:
            async with client(server) as operator:
                await operator.hello()
                await operator.send_raw('{"type": "act", "action": "fly", "source": "xr_menu"}')
                error = await operator.wait_for(lambda x: isinstance(x, m.Error))
                assert isinstance(error, m.Error) and error.code == "malformed"
                assert "fly" in error.message and "restart_trial" in error.message

    asyncio.run(scenario())

"""What a session says reaches its clients only after ``session_started``: the seat takes
the session on and tells its clients before the server's loop serves the session's pipe
(`src/workcell/server/conductor.py`), so an operator never holds a State of a session it
has not been told of, and its first reply to that State (a frame report, an input) finds
the session taken on."""

from __future__ import annotations

import asyncio
from pathlib import Path

from tests.server.harness import FAST_SETTINGS, client, running_server
from tests.server.test_frame_stats import REPORT
from workcell.protocol import messages as m
from workcell.record.store import Store
from workcell.task import events as ev


def test_session_started_comes_before_anything_the_session_says(tmp_path: Path) -> None:
    async def scenario() -> None:
        with running_server(tmp_path) as server:
            async with client(server) as operator, client(server) as spectator:
                await operator.hello()
                await spectator.hello(role="spectator")
                for _ in range(3):
                    operator.received.clear()
                    spectator.received.clear()
                    await operator.send(m.StartSession(settings=FAST_SETTINGS))
                    await operator.wait_for(lambda x: isinstance(x, m.State))
                    await operator.send(REPORT)  # its first reply to the session's State
                    await spectator.wait_for(lambda x: isinstance(x, m.State))
                    for heard in (operator.received, spectator.received):
                        kinds = [type(x).__name__ for x in heard]
                        started = kinds.index("SessionStarted")
                        said = [x for x in heard[:started] if isinstance(x, m.State | ev.TaskEvent)]
                        assert not said, kinds  # nothing of the session before it started
                    await operator.send(m.Stop())
                    await operator.wait_for(lambda x: isinstance(x, m.SessionEnded))
                    await spectator.wait_for(lambda x: isinstance(x, m.SessionEnded))
            with Store.open(server.options.store, writer=False) as store:
                trials = store.trials()
                reports = [
                    e
                    for trial in trials
                    for e in store.events(trial.trial_id)
                    if e.kind == "client_frames"
                ]
            assert len(trials) == 3
            assert len(reports) == 3  # each first reply to a State found its session

    asyncio.run(scenario())

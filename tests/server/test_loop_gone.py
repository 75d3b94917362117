"""A session that outlives the server's event loop: uvicorn can end without the app's
shutdown (a forced exit, a failure inside it), and the loop that serves every session's
pipe (`src/workcell/server/child_link.py`) is then gone while a session still runs and
still sends its States. What ``workcell serve`` does last (``seats.quit()``, then
``seats.finish()``) must still end that session in order: the stop written straight to its
pipe, the pipe drained until the session has closed its trial."""

from __future__ import annotations

import asyncio
import time
from pathlib import Path

from tests.server.harness import FAST_SETTINGS, client, running_server
from workcell.protocol import messages as m
from workcell.record import Store
from workcell.record.verify import verify_store


def test_a_session_left_running_when_the_loop_ended_still_ends_application_quit(
    tmp_path: Path,
) -> None:
    with running_server(tmp_path) as server:
        conductor = server.seats.conductors["1"]

        async def scenario() -> float:
            async with client(server) as operator:
                await operator.hello()
                await operator.send(m.StartSession(settings=dict(FAST_SETTINGS)))
                await operator.wait_for(lambda x: isinstance(x, m.State))
                server.server.force_exit = True  # no lifespan shutdown: the sessions run on
                server.server.should_exit = True
                loop = conductor.loop
                assert loop is not None
                while loop.is_running():
                    await asyncio.sleep(0.05)
            assert conductor.session is not None and conductor.session.running
            # the session goes on sending States nobody reads: enough to fill its pipe
            await asyncio.sleep(3.0)
            server.seats.quit()
            began = time.monotonic()
            assert server.seats.finish(30.0), "the session did not end"
            return time.monotonic() - began

        took = asyncio.run(scenario())
    assert took < 15.0, f"finish waited {took:.1f} s"  # the drain let the session end at once
    store = server.options.store
    assert verify_store(store) == []
    with Store.open(store, writer=False) as reader:
        (session,) = reader.sessions()
        (trial,) = reader.trials()
        frames = len(reader.frames(trial.trial_id)["t_sim"])
    assert (trial.outcome, trial.interruption_reason) == ("interrupted", "application_quit")
    assert session.status == "interrupted"
    assert frames > 0

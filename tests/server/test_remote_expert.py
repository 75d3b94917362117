"""A remote operator with the expert's behaviour (``bench/crowd_operator.py``, what
``bench/crowd.py`` loads the server with) delivers a box over a real socket, seeing only
what a browser sees: the protocol carries everything a person needs to do the task."""

from __future__ import annotations

import asyncio
import json
import time
from pathlib import Path

import pytest
from bench.crowd_operator import ExpertLikeHeadset

from tests.server.harness import client, running_server
from workcell.protocol import messages as m
from workcell.record import Store

SETTINGS: dict[str, object] = {"task": {"countdown_s": 0.0, "time_limit_s": 120.0}, "seed": 3}
INPUT_PERIOD_S = 1 / 72
STALL_S = 60.0
"""How long the simulated time may stand still before the test gives up. The trial's own
limit (120 s of simulated time) ends the session otherwise, however far below real time a
busy machine runs it: no wall-clock budget to miss."""


@pytest.mark.slow
def test_an_expert_like_remote_operator_delivers_a_box(tmp_path: Path) -> None:
    async def scenario() -> dict[str, object]:
        with running_server(tmp_path) as server:
            async with client(server) as c:
                await c.hello()
                await c.send(m.StartSession(settings=SETTINGS))
                headset = ExpertLikeHeadset()
                ended: dict[str, object] = {}
                simulated = {"t_sim": -1.0, "at": time.monotonic()}

                async def listen() -> None:
                    async for text in c.connection:
                        message = json.loads(text)
                        headset.view.take(message)
                        if message["type"] == "state" and message["t_sim"] > simulated["t_sim"]:
                            simulated.update(t_sim=message["t_sim"], at=time.monotonic())
                        if message["type"] == "session_ended":
                            ended.update(message)
                            return

                listener = asyncio.create_task(listen())
                seq = 0
                while not listener.done() and time.monotonic() - simulated["at"] < STALL_S:
                    seq += 1
                    await c.send(headset.input(seq, lead_s=0.05))
                    await asyncio.sleep(INPUT_PERIOD_S)
                if not listener.done():
                    listener.cancel()
                    raise AssertionError(
                        f"the simulated time stayed at {simulated['t_sim']} s for {STALL_S:g} s; "
                        f"phases {headset.operator.phases}"
                    )
                return ended

    ended = asyncio.run(scenario())
    assert ended["reason"] == "completed", ended
    assert (ended["trials"], ended["successes"]) == (1, 1), ended
    with Store.open(tmp_path / "store.sqlite", writer=False) as reader:
        (trial,) = reader.trials()
        assert trial.outcome == "success"
        frames = reader.frames(trial.trial_id)
        assert max(frames["grip_l"]) == 1.0 and max(frames["trigger_r"]) == 1.0

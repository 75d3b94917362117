"""Start sessions over a real socket and drive the robot with raw Input messages."""

from __future__ import annotations

import asyncio
import math
import sys
from pathlib import Path

import numpy as np

from tests.server.harness import FAST_SETTINGS, body_index, client, hand, running_server
from workcell.protocol import messages as m
from workcell.record.store import Store
from workcell.tasks.registry import BUILT_IN


def test_bad_settings_are_rejected_field_by_field(tmp_path: Path) -> None:
    async def scenario() -> None:
        with running_server(tmp_path) as server:
            async with client(server) as c:
                await c.hello()
                settings: dict[str, object] = {
                    "task": {"mode": "marathon", "time_limit_s": -5, "colour": "red"},
                    "seed": "x",
                }
                await c.send(m.StartSession(settings=settings))
                rejected = await c.wait_for(lambda x: isinstance(x, m.ConfigRejected))
                assert isinstance(rejected, m.ConfigRejected)
                given = {p.path: p.value for p in rejected.problems}
                assert given == {
                    ("task", "mode"): "marathon",
                    ("task", "time_limit_s"): -5,
                    ("task", "colour"): "red",
                    ("seed",): "x",
                }
                for problem in rejected.problems:
                    assert problem.message.startswith(".".join(map(str, problem.path)))
                    assert problem.message.endswith(problem.allowed)
            assert server.conductor.session is None
            assert server.conductor.sessions_started == 0

    asyncio.run(scenario())


def _with_task(kind: str) -> dict[str, object]:
    return {**FAST_SETTINGS, "task": {**FAST_SETTINGS["task"], "kind": kind}}


def test_a_client_starts_only_a_built_in_task(tmp_path: Path) -> None:
    """A client naming module:Class would have the server import a module of its choice:
    refused beside the field, no module imported, nothing started; a built-in task starts."""
    said: dict[str, str] = {}

    async def scenario() -> None:
        with running_server(tmp_path) as server:
            async with client(server) as c:
                await c.hello()
                for kind in ("tests.server.no_such_module:Task", "juggling"):
                    await c.send(m.StartSession(settings=_with_task(kind)))
                    rejected = await c.wait_for(lambda x: isinstance(x, m.ConfigRejected))
                    assert isinstance(rejected, m.ConfigRejected)
                    (problem,) = rejected.problems
                    assert problem.path == ("task", "kind") and problem.value == kind
                    said[kind] = problem.message
                assert server.conductor.sessions_started == 0
                await c.send(m.StartSession(settings=_with_task("box_transfer")))
                await c.wait_for(lambda x: isinstance(x, m.SessionStarted))
                await c.send(m.Stop())
                await c.wait_for(lambda x: isinstance(x, m.SessionEnded))

    asyncio.run(scenario())
    assert (
        f"a client may start only a built-in task ({', '.join(BUILT_IN)})"
        in said["tests.server.no_such_module:Task"]
    )
    assert "no such task" in said["juggling"]
    assert "tests.server.no_such_module" not in sys.modules


def test_left_stick_drives_the_base_forward_and_grip_moves_the_tcp_target(
    tmp_path: Path,
) -> None:
    async def scenario() -> None:
        with running_server(tmp_path) as server:
            async with client(server) as c:
                await c.hello()
                await c.send(m.StartSession(settings=FAST_SETTINGS))
                await c.wait_for(lambda x: isinstance(x, m.SessionStarted))
                scene = await c.wait_for(lambda x: isinstance(x, m.Scene))
                assert isinstance(scene, m.Scene)
                base = body_index(scene, "base")
                first = await c.wait_for(lambda x: isinstance(x, m.State))
                assert isinstance(first, m.State)
                x0, y0 = first.poses[base][:2]
                w, z = first.poses[base][3], first.poses[base][6]
                yaw = 2 * math.atan2(z, w)
                last = 0
                for _ in range(30):  # 0.75 s at full stick
                    last = await c.input(left=hand(stick=(0.0, 1.0)))
                    await asyncio.sleep(0.025)
                state = await c.wait_for(lambda x: isinstance(x, m.State) and x.input_seq == last)
                assert isinstance(state, m.State)
                x1, y1 = state.poses[base][:2]
                forward = (x1 - x0) * math.cos(yaw) + (y1 - y0) * math.sin(yaw)
                sideways = -(x1 - x0) * math.sin(yaw) + (y1 - y0) * math.cos(yaw)
                assert forward > 0.2, forward
                assert abs(sideways) < 0.02

                # grip the left controller and move it 10 cm forward (-z in XR)
                seq = 0
                for i in range(12):
                    z = -0.3 - 0.1 * min(1.0, i / 8)
                    seq = await c.input(left=hand(pose=(0, 1.0, z, 1, 0, 0, 0), grip=1.0))
                    await asyncio.sleep(0.025)
                engaged = await c.wait_for(lambda x: isinstance(x, m.State) and x.input_seq == seq)
                assert isinstance(engaged, m.State)
                assert engaged.following == (True, False)
                # the target moved about 10 cm along the (stopped) base's heading
                yaw = 2 * math.atan2(engaged.poses[base][6], engaged.poses[base][3])
                start = first.tcp_targets[0]
                moved = engaged.tcp_targets[0]
                dx, dy = moved[0] - start[0], moved[1] - start[1]
                along = dx * math.cos(yaw) + dy * math.sin(yaw)
                # the base rolled on a little after the stick was released: compare in base
                # frame via the base displacement
                bx = engaged.poses[base][0] - first.poses[base][0]
                by = engaged.poses[base][1] - first.poses[base][1]
                base_along = bx * math.cos(yaw) + by * math.sin(yaw)
                assert along - base_along > 0.08, (along, base_along)
                await c.send(m.Stop())
                ended = await c.wait_for(lambda x: isinstance(x, m.SessionEnded))
                assert isinstance(ended, m.SessionEnded) and ended.reason == "operator_stop"
            with Store.open(server.options.store, writer=False) as store:
                (trial,) = store.trials()
                assert trial.outcome == "interrupted"
                assert trial.interruption_reason == "operator_stop"
                frames = store.frames(trial.trial_id)
                assert np.nanmax(frames["stick_l_y"]) == 1.0
                assert np.nanmax(frames["grip_l"]) == 1.0
                assert np.nanmin(frames["ctrl_l_z"]) < -0.39

    asyncio.run(scenario())

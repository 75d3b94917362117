"""The operator's browser reports how it draws (frame intervals, draw calls) over a real
socket: each report is recorded as a ``client_frames`` event of the trial under way, is not
echoed to the clients, a spectator's is ignored, and a hostile one is one clear error."""

from __future__ import annotations

import asyncio
import json
from pathlib import Path

import pytest

from tests.server.harness import FAST_SETTINGS, client, running_server
from workcell.protocol import messages as m
from workcell.record.store import Store
from workcell.task import events as ev

REPORT = m.FrameStats(
    frames=300,
    frame_ms_p50=16.7,
    frame_ms_p95=22.4,
    frame_ms_max=48.0,
    draw_calls=41,
    triangles=52_310,
    presenting=False,
)


def test_the_operators_frame_reports_are_recorded_with_the_trial(tmp_path: Path) -> None:
    async def scenario() -> None:
        with running_server(tmp_path) as server:
            async with client(server) as operator, client(server) as spectator:
                await operator.hello()
                await spectator.hello(role="spectator")
                await operator.send(REPORT)  # no session yet: nothing to record it in
                await operator.send(m.StartSession(settings=FAST_SETTINGS))
                await operator.wait_for(lambda x: isinstance(x, m.State))
                await operator.send(REPORT)
                await spectator.send(m.FrameStats(**{**vars(REPORT), "frames": 7}))
                in_headset = m.FrameStats(**{**vars(REPORT), "presenting": True})
                await operator.send(in_headset)
                await asyncio.sleep(0.3)
                await operator.send(m.Stop())
                await operator.wait_for(lambda x: isinstance(x, m.SessionEnded))
                heard = operator.received + spectator.received
            assert not any(isinstance(x, ev.ClientFrames) for x in heard)  # record only
            assert not any(isinstance(x, m.Error) for x in heard)
            with Store.open(server.options.store, writer=False) as store:
                (trial,) = store.trials()
                reports = [e for e in store.events(trial.trial_id) if e.kind == "client_frames"]
            assert [e.payload for e in reports] == [
                {"trial_index": 0, **_figures(REPORT)},
                {"trial_index": 0, **_figures(in_headset)},
            ]
            assert all(e.t_sim is not None and e.t_sim >= 0 for e in reports)

    asyncio.run(scenario())


def _figures(report: m.FrameStats) -> dict[str, object]:
    figures = dict(vars(report))
    del figures["type"]
    return figures


@pytest.mark.parametrize(
    ("field", "value", "code", "allowed"),
    [
        ("frame_ms_p95", "NaN", "invalid_value", "must be a finite number (within +-1.8e308)"),
        ("frame_ms_max", -1.0, "invalid_value", "must be from 0 to 60000"),
        ("draw_calls", 10**9, "invalid_value", "must be from 0 to 1e+06"),
        ("presenting", 1, "malformed", "must be true or false"),
    ],
)
def test_a_hostile_frame_report_is_one_clear_error(
    tmp_path: Path, field: str, value: object, code: str, allowed: str
) -> None:
    async def scenario() -> None:
        with running_server(tmp_path) as server:
            async with client(server) as operator:
                await operator.hello()
                body = {**vars(REPORT), field: value}
                text = json.dumps(body).replace('"NaN"', "NaN")
                await operator.send_raw(text)
                error = await operator.wait_for(lambda x: isinstance(x, m.Error))
                assert isinstance(error, m.Error) and error.code == code
                assert error.message.startswith(f"frame_stats.{field} = ")
                assert error.message.endswith(allowed)
                await operator.send(m.Ping(t_client=1.0))  # the link stays up
                pong = await operator.wait_for(lambda x: isinstance(x, m.Pong))
                assert isinstance(pong, m.Pong)

    asyncio.run(scenario())

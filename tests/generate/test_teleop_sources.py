"""Generation from a trial recorded through the teleop path: a real ``workcell serve``
(uvicorn on a free port, its session in a process of its own), a scripted remote operator
over a real WebSocket sending an emulated headset's inputs (``bench/teleop_sources.py``),
then ``workcell generate`` from the store the server recorded, in D1."""

from __future__ import annotations

import asyncio
import json
from pathlib import Path

import numpy as np
import pytest
from bench.teleop_sources import OPERATOR_ID, drive_session, session_settings

from tests.server.harness import running_server
from workcell.cli.main import main
from workcell.generate.source import load_sources
from workcell.record import Store


@pytest.mark.slow
def test_attempts_are_generated_from_a_serve_recorded_teleop_trial(tmp_path: Path) -> None:
    with running_server(tmp_path) as server:
        recorded = asyncio.run(drive_session(server.ws, session_settings(trials=1, seed=1)))
    assert (recorded.reason, recorded.trials, recorded.successes) == ("completed", 1, 1)
    store = tmp_path / "store.sqlite"
    (source,) = load_sources(store, "box_transfer")
    # a person's trial: the arms follow only while a grip is held, the box is taken as it
    # creeps off the belt (never at rest 0.5 s frame by frame: the segmenter's fallback)
    assert source.operator_id == OPERATOR_ID
    assert not source.follow.all() and source.follow.any()

    out = tmp_path / "generated.sqlite"
    argv = ["generate", "--source", str(store), "--attempts", "3", "--seed", "7"]
    assert main([*argv, "--store", str(out), "--world", "D1"]) == 0
    with Store.open(out, writer=False) as reader:
        events = [e.payload for e in reader.events() if e.kind == "generation"]
        trials = reader.trials()
    assert len(events) == len(trials) == 3
    assert {e["source_trial_id"] for e in events} == {source.trial_id}
    accepted = [e for e in events if e["accepted"]]
    assert accepted, json.dumps([e["reason"] for e in events])
    for event in accepted:
        assert event["recheck"]["held"] and event["stage"] == "delivered"
        moved = [s["transform"] for s in event["segments"]]
        assert any(np.hypot(m["x"], m["y"]) > 1e-3 for m in moved)  # re-targeted into D1

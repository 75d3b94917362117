"""Study control in the browser (real headless Chromium, ``web/tests/e2e/study_control.ts``):
a participant pauses with the key (the overlay says so, the clock stands still), is asked
to confirm a stop and may cancel it, stops with a reason, and resumes their plan's step
from the end screen; the admin stops them from the admin page with a reason they read;
they resume again and finish, and the end screen thanks them. The store recorded it all."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from tests.web.test_browser import (
    _rows,
    browser_available,
    one_browser_at_a_time,
    run_script,
    scripts_compiled,
    serving,
)
from workcell.study.config import load_study
from workcell.study.invites import invites_path, load_or_create
from workcell.study.plan import participant_plan
from workcell.task.runner import trial_seed

__all__ = ["browser_available", "one_browser_at_a_time", "scripts_compiled"]  # fixtures

STUDY = """name = "control"
participants = 1
instructions = "Move the box to the green zone."
consent = "I agree that my teleoperation is recorded."
[session]
task = { countdown_s = 0.0, time_limit_s = 8.0 }
[[conditions]]
name = "assisted"
settings = { "world.grasp" = "assisted" }
[[steps]]
mode = "collection"
trials = 3
"""

pytestmark = [pytest.mark.slow, pytest.mark.browser]


def test_pause_confirmed_stop_with_a_reason_and_the_end_screens_next_step(
    tmp_path: Path, one_browser_at_a_time: None
) -> None:
    study_file = tmp_path / "control.toml"
    study_file.write_text(STUDY, encoding="utf-8")
    study = load_study(study_file)
    (planned,) = participant_plan(study, "p01")
    invites = load_or_create(invites_path(tmp_path / "store.sqlite", study), study)
    with serving(tmp_path, "--study", str(study_file), token=invites.admin) as server:
        result = run_script("study_control", server, invites.participants["p01"], invites.admin)
    sessions = _rows(server.store, "SELECT * FROM sessions ORDER BY created_wall")
    assert [(s["session_id"], s["status"]) for s in sessions] == [
        (result["first"], "interrupted"),
        (result["second"], "interrupted"),
        (result["third"], "completed"),
    ]
    events = _rows(
        server.store,
        "SELECT kind, payload_json FROM events WHERE session_id = ? ORDER BY seq",
        result["first"],
    )
    kinds = [e["kind"] for e in events]
    # paused with P, resumed with the overlay's button, paused again, stopped while paused
    assert [k for k in kinds if k in ("paused", "resumed", "stop_requested")] == [
        "paused",
        "resumed",
        "paused",
        "resumed",
        "stop_requested",
    ]
    payloads = [json.loads(e["payload_json"]) for e in events]
    first_pause = next(p for e, p in zip(kinds, payloads, strict=True) if e == "resumed")
    assert first_pause["paused_s"] >= 1.5  # the script waited 1.5 s and more while paused
    stop = next(p for e, p in zip(kinds, payloads, strict=True) if e == "stop_requested")
    assert (stop["by"], stop["reason"]) == ("operator", "I need a short break")
    first_trials = _rows(
        server.store,
        "SELECT * FROM trials WHERE session_id = ? ORDER BY trial_index",
        result["first"],
    )
    assert [(t["outcome"], t["interruption_reason"]) for t in first_trials] == [
        ("timeout", None),
        ("interrupted", "operator_stop"),
    ]
    seed = planned.config.seed
    second_trials, third_trials = (
        _rows(
            server.store,
            "SELECT * FROM trials WHERE session_id = ? ORDER BY trial_index",
            result[which],
        )
        for which in ("second", "third")
    )
    # each start goes on where the last stopped, each trial in the world the plan gave it
    assert [(t["trial_seed"], t["outcome"]) for t in second_trials] == [
        (trial_seed(seed, 1), "timeout"),
        (trial_seed(seed, 2), "interrupted"),
    ]
    assert second_trials[1]["interruption_reason"] == "admin_stop"
    assert [(t["trial_seed"], t["outcome"]) for t in third_trials] == [
        (trial_seed(seed, 2), "timeout")
    ]
    assert third_trials[0]["elapsed_s"] == 8.0
    (admin_stop,) = _rows(
        server.store,
        "SELECT payload_json FROM events WHERE session_id = ? AND kind = 'stop_requested'",
        result["second"],
    )
    assert json.loads(admin_stop["payload_json"])["by"] == "admin"
    assert json.loads(admin_stop["payload_json"])["reason"] == "the lab closes in five minutes"


QUEUE_STUDY = """name = "queue"
participants = 2
instructions = "Move the box to the green zone."
consent = "I agree that my teleoperation is recorded."
[session]
task = { countdown_s = 0.0, time_limit_s = 120.0 }
[[conditions]]
name = "assisted"
settings = { "world.grasp" = "assisted" }
[[steps]]
mode = "practice"
"""


def test_a_start_without_headroom_waits_with_its_position_and_starts_by_itself(
    tmp_path: Path, one_browser_at_a_time: None
) -> None:
    """``--admit-cores 0.01``: one running session leaves no room for another, so p02's
    start waits (the page's banner: position 1 of 1, and why) until p01 stops."""
    study_file = tmp_path / "queue.toml"
    study_file.write_text(QUEUE_STUDY, encoding="utf-8")
    study = load_study(study_file)
    invites = load_or_create(invites_path(tmp_path / "store.sqlite", study), study)
    extra = ("--study", str(study_file), "--sessions", "2", "--admit-cores", "0.01")
    with serving(tmp_path, *extra, token=invites.admin) as server:
        tokens = (invites.participants["p01"], invites.participants["p02"])
        result = run_script("study_queue", server, *tokens)
    first, second = _rows(server.store, "SELECT * FROM sessions ORDER BY created_wall")
    assert (first["session_id"], first["operator_id"]) == (result["first"], "p01")
    assert (second["session_id"], second["operator_id"]) == (result["second"], "p02")
    assert second["created_wall"] >= first["ended_wall"]  # it waited for p01's end

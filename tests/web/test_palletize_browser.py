"""Palletize in the browser: the setup page offers the task, and desktop input (keyboard and
mouse, through the real client in chromium) drives the robot to the task's first stages,
a box grasped on the way to the pallet. The fixtures are the browser tests' own
(:mod:`tests.web.test_browser`)."""

from __future__ import annotations

import json

import pytest

from tests.web.test_browser import (
    Server,
    _rows,
    browser_available,
    one_browser_at_a_time,
    run_script,
    scripts_compiled,
    server,
)
from workcell.tasks.palletize.stages import PALLETIZE_STAGES

__all__ = ["browser_available", "one_browser_at_a_time", "scripts_compiled", "server"]

pytestmark = [pytest.mark.slow, pytest.mark.browser]


def test_desktop_input_drives_palletize_to_a_grasped_box(server: Server) -> None:
    result = run_script("palletize_desktop", server)
    stages = result["stages"]
    assert stages[0] == "none" and stages[-1] == "grasped"
    assert [s for s in PALLETIZE_STAGES if s in stages] == stages  # in the task's order
    assert result["base_moved_m"] > 0.2
    (session,) = _rows(
        server.store, "SELECT * FROM sessions WHERE session_id = ?", result["session_id"]
    )
    assert json.loads(session["parameters_json"])["task"]["kind"] == "palletize"
    (trial,) = _rows(
        server.store, "SELECT * FROM trials WHERE session_id = ?", session["session_id"]
    )
    assert trial["outcome"] == "interrupted"
    grasps = _rows(
        server.store,
        "SELECT payload_json FROM events WHERE trial_id = ? AND kind = 'grasp_changed'",
        trial["trial_id"],
    )
    assert any(json.loads(g["payload_json"])["engaged"] for g in grasps)

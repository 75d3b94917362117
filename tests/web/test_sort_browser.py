"""The sort task in the real web client, driven with desktop input (keyboard only) to its
first stage: the setup page offers "sort", the first box comes to rest at the end of the
belt, the robot drives up to it, both hands are lowered onto it and the HUD says
``touched``; the store records the session's task, the trial's sort layout and the frames
in which a pad touched the box.

Reuses the server and browser harness of :mod:`tests.web.test_browser` (the script is
``web/tests/e2e/sort_desktop.ts``)."""

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

pytestmark = [pytest.mark.slow, pytest.mark.browser]
__all__ = ["browser_available", "one_browser_at_a_time", "scripts_compiled"]
"""The harness's fixtures, used in this module (the first and the last for every test)."""


@pytest.mark.usefixtures("one_browser_at_a_time")
def test_desktop_keys_drive_sort_to_its_first_stage(tmp_path: Path) -> None:
    with serving(tmp_path) as server:
        result = run_script("sort_desktop", server)
    assert result["task"] == "sort" and result["stage"] == "touched"
    assert result["source"] == "desktop"
    assert result["base_moved_m"] > 0.3
    assert {"g", "h", "v", "Comma"} <= set(result["keys_used"])
    (session,) = _rows(server.store, "SELECT * FROM sessions")
    assert session["session_id"] == result["session_id"]
    assert json.loads(session["parameters_json"])["task"]["kind"] == "sort"
    (trial,) = _rows(server.store, "SELECT * FROM trials")
    (started,) = _rows(
        server.store,
        "SELECT payload_json FROM events WHERE trial_id = ? AND kind = 'trial_started'",
        trial["trial_id"],
    )
    layout = json.loads(started["payload_json"])["conditions"]["task"]
    assert sorted(layout["box_kinds"]) == [0.0, 0.0, 1.0, 1.0]
    touches = _rows(
        server.store,
        "SELECT frame_index FROM frames WHERE trial_id = ? AND (contact_l >= 0 OR contact_r >= 0)",
        trial["trial_id"],
    )
    assert touches, "no recorded frame shows a pad touching the box"

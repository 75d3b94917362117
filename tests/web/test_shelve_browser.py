"""The shelve task in the real web client, driven with desktop input (keyboard only) to
its first stage: the setup page offers "shelve", the robot drives to the box waiting on
the table, both hands are lowered onto it and the HUD says ``touched``; the store records
the session's task, the trial's asked shelf and the frames in which a pad touched the box.

Reuses the server and browser harness of :mod:`tests.web.test_browser` (the script is
``web/tests/e2e/shelve_desktop.ts``)."""

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
from workcell.tasks.shelve.shelf import SHELF_NAMES
from workcell.tasks.shelve.task import Shelve

pytestmark = [pytest.mark.slow, pytest.mark.browser]
__all__ = ["browser_available", "one_browser_at_a_time", "scripts_compiled"]
"""The harness's fixtures, used in this module (the first and the last for every test)."""


@pytest.mark.usefixtures("one_browser_at_a_time")
def test_desktop_keys_drive_shelve_to_its_first_stage(tmp_path: Path) -> None:
    with serving(tmp_path) as server:
        result = run_script("shelve_desktop", server)
    assert result["task"] == "shelve" and result["stage"] == "touched"
    assert result["source"] == "desktop"
    assert result["base_moved_m"] > 0.5
    assert {"g", "h", "v", "Comma"} <= set(result["keys_used"])
    (session,) = _rows(server.store, "SELECT * FROM sessions")
    assert session["session_id"] == result["session_id"]
    assert json.loads(session["parameters_json"])["task"]["kind"] == "shelve"
    (trial,) = _rows(server.store, "SELECT * FROM trials")
    (started,) = _rows(
        server.store,
        "SELECT payload_json FROM events WHERE trial_id = ? AND kind = 'trial_started'",
        trial["trial_id"],
    )
    conditions = json.loads(started["payload_json"])["conditions"]
    asked = conditions["task"]["shelf"]
    assert asked in (0, 1, 2)
    # the HUD showed the shelf asked for, in the sentence the exports carry
    assert SHELF_NAMES[asked] in result["hud_instruction"]
    assert result["hud_instruction"] == Shelve().trial_instruction(1, conditions)
    touches = _rows(
        server.store,
        "SELECT frame_index FROM frames WHERE trial_id = ? AND (contact_l >= 0 OR contact_r >= 0)",
        trial["trial_id"],
    )
    assert touches, "no recorded frame shows a pad touching the box"

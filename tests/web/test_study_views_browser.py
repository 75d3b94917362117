"""The researcher's and the operator's views in real headless Chromium (issue 36, points
7, 8 and 9), against the real server (``python -m workcell serve``): the scripts
``web/tests/e2e/first_screen.ts`` and ``study_views.ts`` (fixtures: ``test_browser.py``)."""

from __future__ import annotations

from pathlib import Path

import pytest

from tests.web.test_browser import (
    Server,
    _rows,
    browser_available,
    one_browser_at_a_time,
    run_script,
    scripts_compiled,
    server,
    serving,
)
from workcell.study.config import load_study
from workcell.study.invites import invites_path, load_or_create
from workcell.study.plan import participant_plan

__all__ = ["browser_available", "one_browser_at_a_time", "scripts_compiled", "server"]
"""The fixtures of test_browser.py, used here by name (the module-wide ones by themselves)."""

STUDY = """name = "views"
participants = 2
instructions = "Move the box to the green zone."
consent = "I agree that my teleoperation is recorded."
[session]
task = { countdown_s = 0.0, time_limit_s = 15.0 }
[[conditions]]
name = "assisted"
settings = { "world.grasp" = "assisted" }
[[conditions]]
name = "physical"
settings = { "world.grasp" = "physical" }
[[steps]]
mode = "practice"
"""

pytestmark = [pytest.mark.slow, pytest.mark.browser]


def test_first_screen_hud_score_and_key_map(server: Server) -> None:
    """A few choices and Start in view, the rest under Advanced; the HUD's score is the
    end's; the key map opens once, then as the operator left it."""
    result = run_script("first_screen", server)
    assert result["first_screen"] == ["task.kind", "world.grasp", "operator_id"]
    assert result["end_score"] == 0
    (trial,) = _rows(
        server.store, "SELECT * FROM trials WHERE session_id = ?", result["session_id"]
    )
    assert (trial["outcome"], trial["score"], trial["boxes_delivered"]) == ("timeout", 0, 0)
    (session,) = _rows(server.store, "SELECT * FROM sessions")
    assert session["operator_id"] == "e2e-first"


def test_admin_watches_filters_downloads_and_replays_a_participants_trial(
    tmp_path: Path, one_browser_at_a_time: None
) -> None:
    study_file = tmp_path / "views.toml"
    study_file.write_text(STUDY, encoding="utf-8")
    study = load_study(study_file)
    invites = load_or_create(invites_path(tmp_path / "store.sqlite", study), study)
    with serving(tmp_path, "--study", str(study_file), token=invites.admin) as running:
        result = run_script("study_views", running, invites.participants["p01"], invites.admin)
    (session,) = _rows(running.store, "SELECT * FROM sessions")
    assert session["session_id"] == result["session_id"] and session["operator_id"] == "p01"
    assert result["condition"] == participant_plan(study, "p01")[0].condition
    (trial,) = _rows(running.store, "SELECT * FROM trials")
    assert trial["n_frames"] == result["frames"]
    assert 0.85 < result["replay_rate"] < 1.1
    assert result["replay_skipped"] > 0  # the slowed renderer kept time by skipping frames

"""A person corrects the expert from the desktop page and from the emulated headset (issue
35): real server over a real socket, the real client in headless chromium. The person takes
over (T on the desktop; both grips held in the headset), moves an arm, hands back, and the
expert still delivers; the record says who drove each frame, with the take-over and
hand-back events naming the person and the driver. The fixtures are the browser tests'
own (:mod:`tests.web.test_browser`)."""

from __future__ import annotations

import json
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
)

__all__ = ["browser_available", "one_browser_at_a_time", "scripts_compiled", "server"]

pytestmark = [pytest.mark.slow, pytest.mark.browser]


def check_corrected_trial(
    store: Path, session_id: str, operator_id: str, driver: str = "expert"
) -> list[dict[str, object]]:
    """The session's one trial: driven by ``driver`` (the expert: and delivered), with one
    stretch of corrected frames between one take-over and one hand-back; its take-over
    events."""
    (trial,) = _rows(store, "SELECT * FROM trials WHERE session_id = ?", session_id)
    assert trial["driver"] == driver
    if driver == "expert":
        assert (trial["outcome"], trial["boxes_delivered"]) == ("success", 1)
    else:
        assert trial["outcome"] in ("success", "timeout")
    flags = [
        row["intervention"]
        for row in _rows(
            store,
            "SELECT intervention FROM frames WHERE trial_id = ? ORDER BY frame_index",
            trial["trial_id"],
        )
    ]
    corrected = [i for i, flag in enumerate(flags) if flag == 1.0]
    assert corrected and set(flags) == {0.0, 1.0}
    assert corrected == list(range(corrected[0], corrected[-1] + 1))
    assert flags[-1] == 0.0  # the driver drove to the end
    events = [
        (row["kind"], json.loads(row["payload_json"]))
        for row in _rows(
            store,
            "SELECT kind, payload_json FROM events WHERE trial_id = ? "
            "AND kind IN ('take_over', 'hand_back') ORDER BY seq",
            trial["trial_id"],
        )
    ]
    assert [kind for kind, _ in events] == ["take_over", "hand_back"]
    for _, payload in events:
        assert (payload["operator_id"], payload["driver"]) == (operator_id, driver)
    return [payload for _, payload in events]


def test_the_person_takes_over_from_the_expert_on_the_desktop(server: Server) -> None:
    result = run_script("take_over_desktop", server)
    assert result["successes"] == 1
    assert result["raised_m"] > 0.05  # the arm followed the person's hand up
    assert "you (took over from expert)" in str(result["driving_line"])
    check_corrected_trial(server.store, str(result["session_id"]), "e2e-corrector")


def test_the_person_takes_over_from_the_expert_in_the_headset(server: Server) -> None:
    result = run_script("xr_take_over", server)
    assert result["successes"] == 1
    assert result["raised_m"] > 0.05  # the left arm followed the controller up
    check_corrected_trial(server.store, str(result["session_id"]), "e2e-xr-corrector")

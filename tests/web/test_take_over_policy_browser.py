"""A person corrects a learned policy from the desktop page and from the emulated headset
(issue 35): a tiny ACT policy trained 2 steps with the real LeRobot
(:mod:`tests.learn.test_policy_correction`) drives; the person takes over, moves an arm,
hands back, and the policy drives on to the trial's end; the record names the policy as
the driver of every trial and of each take-over."""

from __future__ import annotations

from pathlib import Path

import pytest

from tests.export.conftest import lerobot_dir, recorded
from tests.learn.test_policy_correction import tiny_policy
from tests.web.test_browser import (
    Server,
    browser_available,
    one_browser_at_a_time,
    run_script,
    scripts_compiled,
    server,
)
from tests.web.test_take_over_browser import check_corrected_trial
from workcell.learn.checkpoint import PolicyCheckpoint

__all__ = [
    "browser_available",
    "lerobot_dir",
    "one_browser_at_a_time",
    "recorded",
    "scripts_compiled",
    "server",
    "tiny_policy",
]

pytestmark = [pytest.mark.slow, pytest.mark.browser]


@pytest.mark.parametrize(
    ("script", "person"),
    [("take_over_desktop", "e2e-corrector"), ("xr_take_over", "e2e-xr-corrector")],
)
def test_the_person_takes_over_from_a_policy(
    server: Server, tiny_policy: Path, script: str, person: str
) -> None:
    result = run_script(script, server, f"policy:{tiny_policy}")
    driver = f"policy:{PolicyCheckpoint.locate(tiny_policy).operator_id}"
    assert result["driver"] == driver and result["reason"] == "completed"
    assert result["raised_m"] > 0.05  # the arm followed the person's hand up
    check_corrected_trial(server.store, str(result["session_id"]), person, driver)

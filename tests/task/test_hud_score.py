"""The HUD's score is what the trial's end will say: the points earned so far, with the
time bonus a success would add shown apart (issue 36: it counted down from 119 with
nothing delivered, then the end screen said 0)."""

from __future__ import annotations

from tests.task.test_runner import make_runner
from workcell.session.config import TaskConfig
from workcell.task.hud import Hud, HudPhase
from workcell.tasks.elements.expert import ExpertOperator


def test_with_nothing_delivered_the_hud_scores_zero_and_the_timeout_ends_with_zero() -> None:
    runner, _ = make_runner(TaskConfig(mode="practice", time_limit_s=2.0, countdown_s=0.0))
    runner.start()
    seen: list[Hud] = []
    while runner.phase is not HudPhase.FINISHED:
        runner.step()
        seen.append(runner.hud())
    running = [h for h in seen if h.phase is HudPhase.RUNNING]
    assert running and all(h.score == 0 for h in running)
    assert running[0].time_bonus == 2 and running[-1].time_bonus in (0, 1)
    (result,) = runner.results
    assert (result.outcome, result.score) == ("timeout", 0)


def test_a_success_ends_with_the_hud_score_and_its_time_bonus() -> None:
    runner, _ = make_runner(TaskConfig(mode="practice", countdown_s=0.0), ExpertOperator())
    runner.start()
    last_running: Hud | None = None
    while runner.phase is not HudPhase.FINISHED:
        hud = runner.hud()
        if hud.phase is HudPhase.RUNNING:
            last_running = hud
        runner.step()
    (result,) = runner.results
    assert result.outcome == "success" and last_running is not None
    box_points = runner.config.task.box_score * result.boxes_done
    assert last_running.score in (0, box_points)  # the delivery may end the trial at once
    # the end adds the time bonus the HUD showed (a step later it may have lost a second)
    assert result.score - box_points in (last_running.time_bonus, last_running.time_bonus - 1)

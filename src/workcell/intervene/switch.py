"""Take-over and hand-back as the live session applies them: the operator switches and the
trial records who took or gave control, the driver and the person's reason."""

from __future__ import annotations

from typing import Any

from workcell.intervene.operator import InterveningOperator
from workcell.task import events as ev
from workcell.task.runner import SessionRunner


def switch(
    operator: InterveningOperator[Any],
    runner: SessionRunner,
    person: bool,
    operator_id: str,
    reason: str,
) -> bool:
    """The person takes control (``person``) or hands it back, at this control period;
    recorded as a ``take_over`` or ``hand_back`` event of the trial under way (or counting
    down). False (nothing recorded) when it was so already or the session is over."""
    world = runner.sim.world
    if runner.current is None:
        return False
    changed = operator.take_over(world) if person else operator.hand_back(world)
    if not changed:
        return False
    kind = ev.TookOver if person else ev.HandedBack
    driver = operator.driver_name
    runner.note(lambda i, t: kind(i, t, operator_id, driver, reason))
    return True

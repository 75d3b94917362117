"""A store whose trials a person corrected: the expert drives a collection session headless
(as fast as the machine goes) through the same operator a live session with ``driver =
"expert"`` runs, and at fixed trial times a take-over and a hand-back are applied as the
live session applies them (:func:`workcell.intervene.switch.switch`). The person sends no
input while they drive, so the robot holds still: the frames between are corrections."""

from __future__ import annotations

from collections.abc import Collection
from pathlib import Path

from workcell.intervene.operator import InterveningOperator
from workcell.intervene.switch import switch
from workcell.recording.drivers import ExpertDriver, InterveningDriver
from workcell.recording.recorded_session import RecordedSession, RecordedSessionConfig
from workcell.session.load import resolve_session_config

TAKE_OVER_S = 1.0
HAND_BACK_S = 2.0
PERSON = "corrector"


def record_corrected(
    store: Path,
    trials: int = 2,
    time_limit_s: float = 3.0,
    taken: Collection[int] | None = None,
    person: str = PERSON,
) -> None:
    """``trials`` collection trials of ``time_limit_s`` (timeouts), those whose index is in
    ``taken`` (None: every one) taken over at :data:`TAKE_OVER_S` and handed back at
    :data:`HAND_BACK_S` by ``person``."""
    config = resolve_session_config(
        flags={
            "task.mode": "collection",
            "task.countdown_s": 0.0,
            "task.time_limit_s": time_limit_s,
            "operator_id": person,
            "driver": "expert",
        }
    )
    recorded = RecordedSessionConfig(
        session=config,
        driver=InterveningDriver(ExpertDriver()),
        store=store,
        writer="inline",
        max_trials=trials,
    )
    with RecordedSession.open(recorded) as session:
        operator = session.operator
        assert isinstance(operator, InterveningOperator)

        def after_step() -> None:
            runner = session.runner
            current = runner.current
            if current is None or (taken is not None and current.trial_index not in taken):
                return
            t = runner.trial_time
            if TAKE_OVER_S <= t < HAND_BACK_S and not operator.person_drives:
                switch(operator, runner, True, person, "scripted")
            elif t >= HAND_BACK_S and operator.person_drives:
                switch(operator, runner, False, person, "")

        assert session.run(after_step=after_step) == "completed"

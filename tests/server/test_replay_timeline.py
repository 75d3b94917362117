"""The replay's event timeline (:mod:`workcell.server.replay_facts`): events on the
trial's clock in time order, without the page's telemetry, each with a one-line detail."""

from __future__ import annotations

from typing import Any

from workcell.record.entries import EventRecord
from workcell.server.replay_facts import DETAIL_CHARACTERS, event_detail, timeline


def event(seq: int, kind: str, t: float | None, **payload: Any) -> EventRecord:
    return EventRecord(f"e{seq}", "s", "t", seq, t, 1000.0 + seq, kind, payload)


def test_the_timeline_is_in_trial_time_without_telemetry_or_session_events() -> None:
    events = [
        event(3, "box_delivered", 4.25, box=0, t_sim=4.25, trial_index=0),
        event(1, "trial_started", 0.0, mode="practice"),
        event(2, "client_frames", 2.0, frames=60),
        event(4, "media", 4.5, videos=[]),
        event(5, "level_changed", None, level=2),
        event(6, "trial_ended", 4.25, outcome="success", score=196),
    ]
    marks = timeline(events)
    assert [(m.t, m.kind) for m in marks] == [
        (0.0, "trial_started"),
        (4.25, "box_delivered"),
        (4.25, "trial_ended"),
    ]
    assert marks[1].detail == "box=0"  # its time and trial are the timeline's own
    assert marks[2].detail == "outcome=success score=196"


def test_a_detail_is_one_short_line() -> None:
    assert event_detail({"speed": 0.123456, "pose": [1, 2, 3], "side": "l", "x": None}) == (
        "speed=0.123 pose=… side=l"
    )
    long = event_detail({f"key{i}": "value" for i in range(30)})
    assert len(long) == DETAIL_CHARACTERS and long.endswith("…")

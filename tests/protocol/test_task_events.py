"""Task events on the wire and in the store: typed messages told apart by ``kind``, the
world's box events declared once, and the stored payload unchanged."""

from __future__ import annotations

import dataclasses
import json
from typing import get_args

import pytest

from workcell.protocol import messages as m
from workcell.protocol.codec import decode_server, encode
from workcell.record.columns import INTERRUPTION_REASONS, OUTCOMES
from workcell.sim import events as world
from workcell.task import events as ev

EXAMPLES: tuple[ev.TaskEvent, ...] = (
    ev.CountdownStarted(0, -3.0, 3.0),
    ev.TrialStarted(0, 0.0, "collection", None, None, 1, 120.0, 2**62 + 1, {"belt": 0.2}),
    ev.BoxReleased(t_sim=0.5, box=2, trial_index=0),
    ev.GraspChanged(1.25, 2, True, trial_index=0),
    ev.BoxDelivered(9.5, 2, 0, 1),
    ev.LevelChanged(0, 9.5, 1, 2, False),
    ev.TrialTimedOut(1, 90.0),
    ev.TrialInterrupted(1, 3.0, "client_lost"),
    ev.OperatorActed(1, 2.5, "restart_trial", "xr_menu"),
    ev.ClientFrames(310, 16.7, 22.4, 48.0, 41, 52_310, True, trial_index=1, t_sim=2.75),
    ev.TrialEnded(1, 3.0, "interrupted", "client_lost", 3.0, 0, 0),
    ev.StopRequested(1, 2.9, "admin", "the room closes"),
    ev.Paused(1, 1.5),
    ev.Resumed(1, 1.5, 12.25),
    ev.TookOver(1, 4.5, "p07", "expert", "it hesitates at the belt"),
    ev.HandedBack(1, 7.25, "p07", "policy:act-run1-1a2b3c", ""),
)


def test_every_event_kind_has_an_example() -> None:
    assert {type(e) for e in EXAMPLES} == set(ev.TASK_EVENTS)


@pytest.mark.parametrize("event", EXAMPLES, ids=lambda e: e.kind)
def test_an_event_crosses_the_wire_flat_and_comes_back_as_its_class(event: ev.TaskEvent) -> None:
    data = json.loads(encode(event))
    assert data["type"] == "event" and data["kind"] == event.kind
    assert "fields" not in data
    assert decode_server(encode(event)) == event


def test_an_unknown_event_kind_is_refused() -> None:
    text = json.dumps({"type": "event", "kind": "box_teleported", "t_sim": 0.0})
    with pytest.raises(Exception, match="box_teleported"):
        decode_server(text)


@pytest.mark.parametrize("event", EXAMPLES, ids=lambda e: e.kind)
def test_the_stored_payload_is_the_trial_index_then_the_events_own_fields(
    event: ev.TaskEvent,
) -> None:
    payload = ev.event_payload(event)
    own = [f.name for f in dataclasses.fields(event) if f.name not in ("t_sim", "kind", "type")]
    assert list(payload) == ["trial_index", *(n for n in own if n != "trial_index")]
    assert ev.event_kind(event) == event.kind


def test_the_box_events_are_the_worlds_stamped_with_the_trial() -> None:
    for task_event, world_event in (
        (ev.BoxReleased, world.BoxReleased),
        (ev.GraspChanged, world.GraspChanged),
        (ev.BoxDelivered, world.BoxCompleted),
    ):
        assert issubclass(task_event, world_event)
        inherited = {f.name for f in dataclasses.fields(world_event)}
        declared = set(task_event.__annotations__)
        assert not inherited & declared, f"{task_event.__name__} declares {inherited & declared}"
    stamped = ev.stamped(world.GraspChanged(5.0, 3, True), 4, 1.5, 0)
    assert stamped == ev.GraspChanged(t_sim=1.5, box=3, engaged=True, trial_index=4)
    delivered = ev.stamped(world.BoxCompleted(5.0, 3), 4, 1.5, 2)
    assert delivered == ev.BoxDelivered(t_sim=1.5, box=3, trial_index=4, boxes_delivered=2)


def test_the_outcome_tuples_are_their_literals() -> None:
    assert get_args(ev.Outcome) == OUTCOMES
    assert get_args(ev.InterruptionReason) == INTERRUPTION_REASONS


def test_the_server_message_union_holds_every_task_event() -> None:
    assert set(ev.TASK_EVENTS) <= set(m.SERVER_MESSAGES)

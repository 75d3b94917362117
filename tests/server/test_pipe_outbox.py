"""The outbox to a session's child over a real pipe: while the child does not read, a
newer input replaces the waiting one, other messages wait in order (the oldest frame
report gives way beyond the bound, never a stop), and all of it arrives once it reads."""

from __future__ import annotations

import multiprocessing
import time

import pytest

from workcell.server import pipe_outbox
from workcell.server.pipe_outbox import PipeOutbox


def _wait_until_blocked(outbox: PipeOutbox, waiting: int) -> None:
    deadline = time.monotonic() + 5
    while outbox.waiting != waiting:
        assert time.monotonic() < deadline, f"{outbox.waiting} waiting, not {waiting}"
        time.sleep(0.01)


def test_a_child_that_does_not_read_costs_one_input_and_loses_nothing_else() -> None:
    child_end, server_end = multiprocessing.Pipe()
    outbox = PipeOutbox(server_end)
    try:
        outbox.put(("frames", b"x" * 1_000_000))  # more than the pipe holds: the sender waits
        _wait_until_blocked(outbox, 0)
        for seq in range(300):
            outbox.put(("input", seq))
        outbox.put(("act", "snap_left"))
        outbox.put(("input", 300))
        outbox.put(("input", 301))
        outbox.put(("stop", "operator_stop"))
        assert outbox.waiting == 4  # input 299, the action, input 301, the stop
        received = [child_end.recv() for _ in range(5)]
    finally:
        outbox.close()
    assert received[0][0] == "frames"
    assert received[1:] == [
        ("input", 299),
        ("act", "snap_left"),
        ("input", 301),
        ("stop", "operator_stop"),
    ]


def test_beyond_the_bound_the_oldest_frame_report_gives_way_never_a_stop(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setattr(pipe_outbox, "MAX_WAITING", 3)
    child_end, server_end = multiprocessing.Pipe()
    outbox = PipeOutbox(server_end)
    try:
        outbox.put(("frames", b"x" * 1_000_000))
        _wait_until_blocked(outbox, 0)
        outbox.put(("stop", "admin_stop"))
        outbox.put(("frames", 1))
        outbox.put(("act", "restart"))
        outbox.put(("frames", 2))  # full: frame report 1 gives way
        outbox.put(("act", "snap_right"))  # full: frame report 2 gives way
        outbox.put(("act", "recenter"))  # full, no report left: the oldest action, not the stop
        assert outbox.waiting == 3
        received = [child_end.recv() for _ in range(4)]
    finally:
        outbox.close()
    assert received[1:] == [("stop", "admin_stop"), ("act", "snap_right"), ("act", "recenter")]

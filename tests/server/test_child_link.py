"""The server's end of a session child's pipe, on a real event loop over a real socket
pair, against multiprocessing's Connection (what the child uses): every message arrives
whole and in order both ways, however the bytes are split; while the child does not read,
a newer input replaces the waiting one and other messages wait in order (the oldest frame
report gives way beyond the bound, never a stop), and all of it arrives once it reads."""

from __future__ import annotations

import asyncio
import multiprocessing
import os
import socket
from multiprocessing.connection import Connection
from typing import Any

import pytest
import uvloop

from workcell.server import pipe_outbox
from workcell.server.child_link import ChildLink, frame

LOOPS = {"asyncio": asyncio.new_event_loop, "uvloop": uvloop.new_event_loop}
"""The standard library's loop, and the server's (``http_config.EVENT_LOOP``)."""


def _run(loop: str, scenario: Any) -> None:
    with asyncio.Runner(loop_factory=LOOPS[loop]) as runner:
        runner.run(scenario)


class _Heard:
    def __init__(self) -> None:
        self.messages: list[tuple[Any, ...]] = []
        self.closed = asyncio.Event()


async def _linked() -> tuple[ChildLink, Connection, _Heard]:
    """A link on the running loop; the child's end as the child has it."""
    child_end, server_end = multiprocessing.Pipe()
    sock = socket.socket(fileno=os.dup(server_end.fileno()))
    server_end.close()
    heard = _Heard()
    link = ChildLink(heard.messages.append, heard.closed.set)
    await asyncio.get_running_loop().connect_accepted_socket(lambda: link, sock)
    return link, child_end, heard


async def _until(check: Any, what: str) -> None:
    for _ in range(500):
        if check():
            return
        await asyncio.sleep(0.01)
    raise AssertionError(f"not {what} within 5 s")


@pytest.mark.parametrize("loop", LOOPS)
def test_messages_arrive_whole_and_in_order_both_ways(loop: str) -> None:
    big = b"s" * 100_000  # longer than Connection writes in one piece (16 KiB)

    async def scenario() -> None:
        link, child, heard = await _linked()
        sent: list[tuple[Any, ...]] = [("state", f'{{"seq":{i}}}', (i, 0.0)) for i in range(200)]
        sent.insert(50, ("scene", big))

        def child_says() -> None:
            for message in sent:
                child.send(message)

        await asyncio.to_thread(child_says)
        await _until(lambda: len(heard.messages) == len(sent), "all heard")
        assert heard.messages == sent
        link.send(("input", 1))
        link.send(("frames", big))
        link.send(("stop", "operator_stop", ""))
        got = [await asyncio.to_thread(child.recv) for _ in range(3)]
        assert got == [("input", 1), ("frames", big), ("stop", "operator_stop", "")]
        child.close()  # the child ends: the link closes once
        await asyncio.wait_for(heard.closed.wait(), 5)
        assert link.closed
        link.send(("input", 2))  # dropped, no error

    _run(loop, scenario())


@pytest.mark.parametrize("loop", LOOPS)
def test_what_is_sent_before_the_connection_is_made_waits_for_it(loop: str) -> None:
    async def scenario() -> None:
        child_end, server_end = multiprocessing.Pipe()
        sock = socket.socket(fileno=os.dup(server_end.fileno()))
        server_end.close()
        link = ChildLink(lambda message: None, lambda: None)
        link.send(("input", 1))
        link.send(("act", "recenter"))
        assert link.waiting == 2
        await asyncio.get_running_loop().connect_accepted_socket(lambda: link, sock)
        got = [await asyncio.to_thread(child_end.recv) for _ in range(2)]
        assert got == [("input", 1), ("act", "recenter")]
        child_end.close()

    _run(loop, scenario())


def test_a_message_split_anywhere_is_put_back_together() -> None:
    heard: list[tuple[Any, ...]] = []
    link = ChildLink(heard.append, lambda: None)
    messages = [("log", 20, "workcell", "x" * n) for n in (0, 1, 300, 70_000)]
    stream = b"".join(frame(message) for message in messages)
    for i in range(0, len(stream), 7):
        link.data_received(stream[i : i + 7])
    assert heard == messages
    link.data_received(stream)  # all of them in one piece
    assert heard == messages * 2


@pytest.mark.parametrize("loop", LOOPS)
def test_a_child_that_does_not_read_costs_one_input_and_loses_nothing_else(loop: str) -> None:
    async def scenario() -> None:
        link, child, _ = await _linked()
        link.send(("frames", b"x" * 2_000_000))  # more than the socket holds: the link waits
        for seq in range(300):
            link.send(("input", seq))
        link.send(("act", "snap_left"))
        link.send(("input", 300))
        link.send(("input", 301))
        link.send(("stop", "operator_stop"))
        assert link.waiting == 4  # input 299, the action, input 301, the stop
        assert link.pending
        received = [await asyncio.to_thread(child.recv) for _ in range(5)]
        assert received[0][0] == "frames"
        assert received[1:] == [
            ("input", 299),
            ("act", "snap_left"),
            ("input", 301),
            ("stop", "operator_stop"),
        ]
        assert link.waiting == 0
        child.close()

    _run(loop, scenario())


@pytest.mark.parametrize("loop", LOOPS)
def test_beyond_the_bound_the_oldest_frame_report_gives_way_never_a_stop(
    loop: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(pipe_outbox, "MAX_WAITING", 3)

    async def scenario() -> None:
        link, child, _ = await _linked()
        link.send(("frames", b"x" * 2_000_000))
        link.send(("stop", "admin_stop"))
        link.send(("frames", 1))
        link.send(("act", "restart"))
        link.send(("frames", 2))  # full: frame report 1 gives way
        link.send(("act", "snap_right"))  # full: frame report 2 gives way
        link.send(("act", "recenter"))  # full, no report left: the oldest action, not the stop
        assert link.waiting == 3
        received = [await asyncio.to_thread(child.recv) for _ in range(4)]
        assert received[1:] == [("stop", "admin_stop"), ("act", "snap_right"), ("act", "recenter")]
        child.close()

    _run(loop, scenario())

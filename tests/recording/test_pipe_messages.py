"""Messages between the recording process and its writer, over a real pipe."""

from __future__ import annotations

import os
import threading

from workcell.recording.pipe_messages import MessageReader, send


def test_messages_arrive_whole_however_the_pipe_cuts_them() -> None:
    read_end, write_end = os.pipe()
    try:
        reader = MessageReader(read_end)
        assert reader.wait(0.0) == []  # nothing yet: returns at once
        with os.fdopen(os.dup(write_end), "wb") as stream:
            send(stream, (3, [("a", 1)]))
            send(stream, "close")
        assert reader.wait(1.0) == [(3, [("a", 1)]), "close"]
        # one message written in two pieces: nothing until it is complete
        with os.fdopen(os.dup(write_end), "wb") as stream:
            send(stream, list(range(1000)))
        data = os.read(read_end, 1 << 16)
        os.write(write_end, data[:10])
        assert reader.wait(1.0) == []
        os.write(write_end, data[10:])
        assert reader.wait(1.0) == [list(range(1000))]
        # a message larger than one read (and than the pipe holds: written by a thread)
        big = b"x" * 300_000
        with os.fdopen(os.dup(write_end), "wb") as stream:
            writer = threading.Thread(target=send, args=(stream, big))
            writer.start()
            got: list[object] = []
            while not got:
                got = reader.wait(1.0)
            writer.join()
        assert got == [big]
    finally:
        os.close(write_end)
        os.close(read_end)


def test_the_end_of_the_pipe_is_none_and_a_cut_message_is_dropped() -> None:
    read_end, write_end = os.pipe()
    reader = MessageReader(read_end)
    with os.fdopen(write_end, "wb") as stream:
        send(stream, "first")
        stream.write(b"\xff\x00\x00\x00partial")  # a message cut short by the sender's death
    messages: list[object] = []
    while None not in messages:
        messages += reader.wait(1.0)
    assert messages == ["first", None]
    assert reader.wait(1.0) == [None]
    os.close(read_end)

"""The shared-memory frame ring between a recording process and its writer."""

from __future__ import annotations

import contextlib
import struct
from collections.abc import Iterator

import numpy as np
import pytest

from workcell.recording.frame_ring import FrameRing


@contextlib.contextmanager
def _made_ring(capacity: int) -> Iterator[FrameRing]:
    """A ring of 4-value rows, removed and unmapped afterwards."""
    ring = FrameRing.create(width=4, capacity=capacity)
    try:
        yield ring
    finally:
        ring.unlink()
        ring.close()


def _rows(start: int, n: int, width: int = 4) -> np.ndarray:
    return np.arange(start * width, (start + n) * width, dtype=np.float64).reshape(n, width)


def test_rows_come_out_in_order_by_trial_and_free_their_space() -> None:
    with _made_ring(8) as writer_side:
        reader_side = FrameRing.attach(writer_side.path, width=4, capacity=8)
        assert writer_side.publish(0, _rows(0, 3), alive=lambda: True) == 3  # rows waiting
        assert writer_side.publish(1, _rows(3, 2), alive=lambda: True) == 5
        # trial 1's start has not arrived: its rows wait
        [(number, rows)] = reader_side.take(trials_known=1)
        assert number == 0 and np.array_equal(rows, _rows(0, 3))
        assert reader_side.consumed == 3 and writer_side.published == 5
        [(number, rows)] = reader_side.take(trials_known=2)
        assert number == 1 and np.array_equal(rows, _rows(3, 2))
        # wrapping around the end of the ring
        assert writer_side.publish(1, _rows(5, 6), alive=lambda: True) == 6
        [(_, rows)] = reader_side.take(upto=8, trials_known=2)
        assert np.array_equal(rows, _rows(5, 3)) and reader_side.consumed == 8
        reader_side.close()


def test_an_incomplete_row_is_not_taken() -> None:
    with _made_ring(8) as writer_side:
        writer_side.publish(0, _rows(0, 2), alive=lambda: True)
        writer_side._rows[1, 2] = -1.0  # as if the row's values were not all visible yet
        taken = writer_side.take(trials_known=1)
        assert [len(rows) for _, rows in taken] == [1]
        assert writer_side.consumed == 1


def test_a_full_ring_waits_for_the_writer_and_stops_when_it_is_gone() -> None:
    calls = []

    def alive() -> bool:
        calls.append(1)
        return len(calls) < 3

    with _made_ring(4) as ring:
        with pytest.raises(BrokenPipeError):
            ring.publish(0, _rows(0, 6), alive=alive)
        assert ring.published == 4 and len(calls) == 3  # it waited, then gave up


def test_a_row_left_from_an_earlier_lap_is_not_taken() -> None:
    with _made_ring(4) as ring:
        ring.publish(0, _rows(0, 4), alive=lambda: True)
        ring.take(trials_known=1)
        # as if the count of a new row were visible before the row itself: the slot still
        # holds position 0's row, whose checksum is complete but for another position
        ring._counts[0] = 5
        assert ring.take(trials_known=1) == [] and ring.consumed == 4
        ring._counts[0] = 4
        ring.publish(0, _rows(4, 1), alive=lambda: True)
        [(_, rows)] = ring.take(trials_known=1)
        assert np.array_equal(rows, _rows(4, 1))


def test_a_batch_across_the_ring_end_comes_out_as_one_run_per_trial() -> None:
    with _made_ring(5) as ring:
        ring.publish(0, _rows(0, 3), alive=lambda: True)
        ring.take(trials_known=1)
        ring.publish(0, _rows(3, 2), alive=lambda: True)
        ring.publish(1, _rows(5, 2), alive=lambda: True)  # wraps: slots 0 and 1
        taken = ring.take(trials_known=2)
        assert [number for number, _ in taken] == [0, 1]
        assert np.array_equal(taken[0][1], _rows(3, 2))
        assert np.array_equal(taken[1][1], _rows(5, 2))
        ring.publish(1, _rows(7, 4), alive=lambda: True)  # slots 2, 3, 4, then 0
        [(number, rows)] = ring.take(trials_known=2)
        assert number == 1 and np.array_equal(rows, _rows(7, 4))


def test_the_file_layout_is_as_documented() -> None:
    """Counts at bytes 0 and 64 (two cache lines: the two processes do not write one
    line), then rows of trial number, values and checksum."""
    with _made_ring(8) as ring:
        ring.publish(3, _rows(0, 2), alive=lambda: True)
        ring.take(trials_known=4)
        raw = ring.path.read_bytes()
        assert struct.unpack_from("=q", raw, 0)[0] == 2
        assert struct.unpack_from("=q", raw, 64)[0] == 2
        first = struct.unpack_from("=5d", raw, 128)
        assert first == (3.0, 0.0, 1.0, 2.0, 3.0)
        words = np.frombuffer(raw, dtype=np.uint64, count=5, offset=128)
        assert struct.unpack_from("=Q", raw, 128 + 5 * 8)[0] == int(words.sum(dtype=np.uint64))

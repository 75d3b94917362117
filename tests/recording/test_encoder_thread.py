"""Camera videos encoded in a thread: every frame, in order; an encoding error reaches the
recorder at its next call, as if it had been raised where the frame was put."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from workcell.errors import RenderError
from workcell.recording.encoder_thread import EncoderThread
from workcell.render import VideoWriter
from workcell.render.video import read_frames


def _frame(level: int) -> np.ndarray:
    return np.full((32, 32, 3), level, dtype=np.uint8)


def test_frames_are_encoded_in_the_order_they_were_put(tmp_path: Path) -> None:
    encoder = EncoderThread()
    writers = [VideoWriter(tmp_path / f"{name}.mp4", 32, 32, 20) for name in ("a", "b")]
    levels = list(range(0, 250, 10))
    for level in levels:
        encoder.put([(writers[0], _frame(level)), (writers[1], _frame(255 - level))])
    encoder.drain()
    for writer in writers:
        writer.close()
    encoder.close()
    for name, expected in (("a", levels), ("b", [255 - v for v in levels])):
        means = [float(f.mean()) for f in read_frames(tmp_path / f"{name}.mp4")]
        assert len(means) == len(levels)
        assert np.abs(np.array(means) - np.array(expected)).max() < 3


def test_an_encoding_error_is_raised_at_the_next_call(tmp_path: Path) -> None:
    encoder = EncoderThread()
    writer = VideoWriter(tmp_path / "v.mp4", 32, 32, 20)
    writer.close()  # writing to it now fails in the thread
    encoder.put([(writer, _frame(0))])
    with pytest.raises(RenderError, match="already closed"):
        encoder.drain()
    encoder.put([(writer, _frame(0))])
    with pytest.raises(RenderError, match="already closed"):
        encoder.drain()
    encoder.drain()  # raised once per error: nothing pending now
    encoder.close()


def test_a_frame_of_the_wrong_shape_is_refused_as_before(tmp_path: Path) -> None:
    encoder = EncoderThread()
    writer = VideoWriter(tmp_path / "v.mp4", 32, 32, 20)
    encoder.put([(writer, np.zeros((16, 16, 3), dtype=np.uint8))])
    with pytest.raises(RenderError, match="needs"):
        for _ in range(10):  # raised at a later put, or at the drain
            encoder.put([(writer, _frame(0))])
        encoder.drain()
    writer.close()
    encoder.close()

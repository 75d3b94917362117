"""Video encoding beside the simulation: rendered frames go to a thread that encodes them.

libx264 (through PyAV) releases the GIL while it encodes, so on a second core a trial's
camera videos are encoded while the simulation steps and renders the next frame. Queueing,
order and errors are :class:`~workcell.recording.frame_thread.FrameThread`'s.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from workcell.recording.frame_thread import FrameThread
from workcell.render import VideoWriter

QUEUE_FRAMES = 4
"""Frames (each: every camera's image) waiting to be encoded before :meth:`put` blocks."""

Item = Sequence[tuple[VideoWriter, NDArray[np.uint8]]]


class EncoderThread(FrameThread[Item]):
    """One thread that writes (writer, image) pairs, in the order they were put."""

    def __init__(self) -> None:
        super().__init__("video-encoder", QUEUE_FRAMES)

    def put(self, item: Item) -> None:
        """Queue one frame's images (blocks while the queue is full)."""
        self._put(item)

    def _work(self, job: Item) -> None:
        for writer, image in job:
            writer.write(image)

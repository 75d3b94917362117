"""Video encoding beside the simulation: rendered frames go to a thread that encodes them.

libx264 (through PyAV) releases the GIL while it encodes, so on a second core a trial's
camera videos are encoded while the simulation steps and renders the next frame. The queue
is short (a few frames), so memory stays bounded and a slow encoder slows the producer
rather than falling behind. An encoding error is kept and raised to the producer at its
next call (:meth:`EncoderThread.put` or :meth:`EncoderThread.drain`), as it would have been
raised by writing in the producer's own thread.
"""

from __future__ import annotations

import queue
import threading
from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from workcell.render import VideoWriter

QUEUE_FRAMES = 4
"""Frames (each: every camera's image) waiting to be encoded before :meth:`put` blocks."""

Item = Sequence[tuple[VideoWriter, NDArray[np.uint8]]]


class EncoderThread:
    """One thread that writes (writer, image) pairs, in the order they were put."""

    def __init__(self) -> None:
        self._queue: queue.Queue[Item | None] = queue.Queue(maxsize=QUEUE_FRAMES)
        self._error: BaseException | None = None
        self._thread = threading.Thread(target=self._run, name="video-encoder", daemon=True)
        self._thread.start()

    def put(self, item: Item) -> None:
        """Queue one frame's images (blocks while the queue is full)."""
        self._raise()
        self._queue.put(item)

    def drain(self) -> None:
        """Wait until every queued frame is written; raise the first error, if any."""
        self._queue.join()
        self._raise()

    def close(self) -> None:
        """Stop the thread once the queue is written (errors are dropped: closing)."""
        if self._thread.is_alive():
            self._queue.put(None)
            self._thread.join()

    def _raise(self) -> None:
        error, self._error = self._error, None
        if error is not None:
            raise error

    def _run(self) -> None:
        while True:
            item = self._queue.get()
            try:
                if item is None:
                    return
                if self._error is None:  # after an error, frames are dropped until raised
                    for writer, image in item:
                        writer.write(image)
            except BaseException as error:  # handed to the producer
                self._error = error
            finally:
                self._queue.task_done()

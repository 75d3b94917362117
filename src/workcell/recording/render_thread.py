"""Camera rendering beside the simulation: each recorded frame's state is copied and the
cameras are drawn from the copy in a thread of their own, which hands the images to the
encoder thread (:mod:`workcell.recording.encoder_thread`).

MuJoCo's OpenGL rendering runs without the GIL, so on a second core the cameras of frame i
are drawn while the simulation steps toward frame i + 1; the pictures are the same as
drawn in the simulation's thread (the same state, the same renderer). The renderer is made
in the thread (an OpenGL context belongs to the thread that made it current) before the
constructor returns, so a machine without offscreen rendering is told at once. The queue is
short, so memory stays bounded (a fixed ring of state copies) and a slow renderer slows
the simulation rather than falling behind. A rendering or encoding error is kept and
raised to the recorder at its next call, as it would have been raised in its own thread.
"""

from __future__ import annotations

import queue
import threading
from collections.abc import Callable, Sequence

import mujoco

from workcell.recording.encoder_thread import EncoderThread
from workcell.render import OffscreenRenderer, VideoWriter

QUEUE_FRAMES = 3
"""Frames waiting to be drawn before :meth:`RenderThread.put` blocks."""
STATE_COPIES = QUEUE_FRAMES + 2
"""State copies in the ring: the queue's, the one being drawn and the one being filled."""

Job = tuple[mujoco.MjData, Sequence[tuple[str, VideoWriter]]]


class RenderThread:
    """Draws ``(camera, writer)`` pairs from copies of the simulation's state, in order."""

    def __init__(self, model: mujoco.MjModel, make_renderer: Callable[[], OffscreenRenderer]):
        self._model = model
        self._copies = [mujoco.MjData(model) for _ in range(STATE_COPIES)]
        self._next = 0
        self._queue: queue.Queue[Job | None] = queue.Queue(maxsize=QUEUE_FRAMES)
        self._error: BaseException | None = None
        self.encoder = EncoderThread()
        self._ready = threading.Event()
        self._renderer: OffscreenRenderer | None = None
        self._thread = threading.Thread(
            target=self._run, args=(make_renderer,), name="camera-render", daemon=True
        )
        self._thread.start()
        self._ready.wait()
        if self._renderer is None:  # it could not be made: say why, here
            self.encoder.close()
            self._raise()

    def put(self, data: mujoco.MjData, pairs: Sequence[tuple[str, VideoWriter]]) -> None:
        """Queue the cameras of the state ``data`` is in now (copied; blocks while the
        queue is full)."""
        self._raise()
        copy = self._copies[self._next]
        self._next = (self._next + 1) % STATE_COPIES
        mujoco.mj_copyData(copy, self._model, data)
        self._queue.put((copy, pairs))

    def drain(self) -> None:
        """Wait until every queued frame is drawn and encoded; raise the first error."""
        self._queue.join()
        self._raise()
        self.encoder.drain()

    def close(self) -> None:
        """Stop both threads once their queues are done (errors are dropped: closing)."""
        if self._thread.is_alive():
            self._queue.put(None)
            self._thread.join()
        self.encoder.close()

    def _raise(self) -> None:
        error, self._error = self._error, None
        if error is not None:
            raise error

    def _run(self, make_renderer: Callable[[], OffscreenRenderer]) -> None:
        try:
            self._renderer = make_renderer()
        except BaseException as error:  # handed to the constructor
            self._error = error
            return
        finally:
            self._ready.set()
        with self._renderer as renderer:
            while True:
                job = self._queue.get()
                try:
                    if job is None:
                        return
                    if self._error is None:  # after an error, frames are dropped until raised
                        data, pairs = job
                        # One draw per camera (not render_all's shared framebuffer, whose
                        # edge pixels may round one grey level apart): the videos stay
                        # byte for byte those of a recorder that draws in its own thread.
                        self.encoder.put(
                            [(writer, renderer.render(data, camera)) for camera, writer in pairs]
                        )
                except BaseException as error:  # handed to the producer
                    self._error = error
                finally:
                    self._queue.task_done()

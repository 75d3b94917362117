"""Camera rendering beside the simulation: each recorded frame's state is copied and the
cameras are drawn from the copy in a thread of their own, which hands the images to the
encoder thread (:mod:`workcell.recording.encoder_thread`).

MuJoCo's OpenGL rendering runs without the GIL, so on a second core the cameras of frame i
are drawn while the simulation steps toward frame i + 1; the pictures are the same as
drawn in the simulation's thread (the same state, the same renderer, one draw per camera).
The renderer is made in the thread (an OpenGL context belongs to the thread that made it
current) before the constructor returns, so a machine without offscreen rendering is told
at once. The state copies are a fixed ring, as long as the queue allows frames in flight;
queueing, order and errors are :class:`~workcell.recording.frame_thread.FrameThread`'s.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import mujoco

from workcell.recording.encoder_thread import EncoderThread
from workcell.recording.frame_thread import FrameThread
from workcell.render import OffscreenRenderer, VideoWriter

QUEUE_FRAMES = 3
"""Frames waiting to be drawn before :meth:`RenderThread.put` blocks."""
STATE_COPIES = QUEUE_FRAMES + 2
"""State copies in the ring: the queue's, the one being drawn and the one being filled."""

Job = tuple[mujoco.MjData, Sequence[tuple[str, VideoWriter]]]


class RenderThread(FrameThread[Job]):
    """Draws ``(camera, writer)`` pairs from copies of the simulation's state, in order."""

    def __init__(self, model: mujoco.MjModel, make_renderer: Callable[[], OffscreenRenderer]):
        self._model = model
        self._copies = [mujoco.MjData(model) for _ in range(STATE_COPIES)]
        self._next = 0
        self._make_renderer = make_renderer
        self._renderer: OffscreenRenderer | None = None
        self.encoder = EncoderThread()
        try:
            super().__init__("camera-render", QUEUE_FRAMES)
        except BaseException:
            self.encoder.close()
            raise

    def put(self, data: mujoco.MjData, pairs: Sequence[tuple[str, VideoWriter]]) -> None:
        """Queue the cameras of the state ``data`` is in now (copied; blocks while the
        queue is full)."""
        copy = self._copies[self._next]
        self._next = (self._next + 1) % STATE_COPIES
        mujoco.mj_copyData(copy, self._model, data)
        self._put((copy, pairs))

    def drain(self) -> None:
        """Wait until every queued frame is drawn and encoded; raise the first error."""
        super().drain()
        self.encoder.drain()

    def close(self) -> None:
        """Stop both threads once their queues are done (errors are dropped: closing)."""
        super().close()
        self.encoder.close()

    def _start(self) -> None:
        self._renderer = self._make_renderer()

    def _stop(self) -> None:
        if self._renderer is not None:
            self._renderer.close()

    def _work(self, job: Job) -> None:
        assert self._renderer is not None
        data, pairs = job
        # One draw per camera (not render_all's shared framebuffer, whose edge pixels may
        # round one grey level apart): the videos stay byte for byte those of a recorder
        # that draws in its own thread.
        self.encoder.put(
            [(writer, self._renderer.render(data, camera)) for camera, writer in pairs]
        )

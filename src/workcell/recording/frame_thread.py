"""A thread that works through a recorder's frames in the order they were put, beside the
simulation: the common part of the camera render thread and the video encoder thread.

The queue is short, so memory stays bounded and a slow thread slows the producer rather
than falling behind. An error in the thread is kept and raised to the producer at its next
call (:meth:`FrameThread.put` or :meth:`FrameThread.drain`), as it would have been raised
had the work been done in the producer's own thread; frames after it are dropped until
then.
"""

from __future__ import annotations

import abc
import queue
import threading
from typing import Generic, TypeVar

Job = TypeVar("Job")


class FrameThread(abc.ABC, Generic[Job]):
    """Runs :meth:`_work` on each job put, in order, in a thread of its own."""

    def __init__(self, name: str, queue_frames: int) -> None:
        self._queue: queue.Queue[Job | None] = queue.Queue(maxsize=queue_frames)
        self._error: BaseException | None = None
        self._ready = threading.Event()
        self._thread = threading.Thread(target=self._run, name=name, daemon=True)
        self._thread.start()
        self._ready.wait()
        self._raise()  # the thread could not start its work: say why, here

    @abc.abstractmethod
    def _work(self, job: Job) -> None:
        """Do one job (in the thread)."""

    def _start(self) -> None:
        """Made ready in the thread before the first job; what it raises, the constructor
        raises."""

    def _stop(self) -> None:
        """Clean up in the thread after the last job."""

    def _put(self, job: Job) -> None:
        self._raise()
        self._queue.put(job)

    def drain(self) -> None:
        """Wait until every job put is done; raise the first error, if any."""
        self._queue.join()
        self._raise()

    def close(self) -> None:
        """Stop the thread once its queue is done (errors are dropped: closing)."""
        if self._thread.is_alive():
            self._queue.put(None)
            self._thread.join()

    def _raise(self) -> None:
        error, self._error = self._error, None
        if error is not None:
            raise error

    def _run(self) -> None:
        try:
            self._start()
        except BaseException as error:  # handed to the constructor
            self._error = error
            return
        finally:
            self._ready.set()
        try:
            while True:
                job = self._queue.get()
                try:
                    if job is None:
                        return
                    if self._error is None:  # after an error, jobs are dropped until raised
                        self._work(job)
                except BaseException as error:  # handed to the producer
                    self._error = error
                finally:
                    self._queue.task_done()
        finally:
            self._stop()

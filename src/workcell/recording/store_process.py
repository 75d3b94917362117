"""A store written by a child process, so that recording costs the simulation little.

The recorder hands over captured frames and events and goes on; the writer process (see
:mod:`workcell.recording.store_worker`) formats, checksums, inserts and commits them on
another core. Frames go through a shared-memory ring (:mod:`workcell.recording.frame_ring`),
copied there in blocks; the writer polls it on its own timer, so that handing frames over
makes no system call and wakes no process (on a virtual machine, waking a process on
another core costs the waker tens of microseconds). Events and other calls go through a
pipe, sent at the next :meth:`StoreProcess.commit`. Calls whose answer the recorder needs
(ids, the end of a session) wait for it, and for every frame handed over before them to be
written. The end of a trial is not waited for, but answered: the recorder reports a
trial's result once the writer has written its end (:meth:`StoreProcess.trial_end_written`).

Guarantees are those of :class:`~workcell.record.store.Store`, kept across the pipe:

- calls are run in the order they are made, each commit's frames in one transaction;
- a failure of a call that was not waited for (disk full, a bad frame) is raised by the
  next call, as the same error class and message;
- if the recording process dies, however it dies, the writer still writes everything
  it was sent and then exits, leaving the running trial for crash recovery; what was
  not yet handed over is at most one commit interval;
- if the writer dies, however it dies, the recording process notices at once (the
  reader thread finds the answer pipe closed: :meth:`StoreProcess.failure_pending`, which
  the recorder asks before each control period) or at the latest at the next hand-over
  (every 0.25 s of sim time: one ``waitpid`` per batch), raises :class:`StorageError`
  naming how it died, and closes the session itself
  (:meth:`StoreProcess.try_interrupt_session`: the trial ``interrupted`` with the reason
  given, ``storage_error``), so that the store says what the operator was told;
- the writer holds the store's writer lock, so no second writer opens the store until
  it has exited.
"""

from __future__ import annotations

import contextlib
import itertools
import math
import os
import queue
import subprocess
import time
from collections.abc import Mapping
from pathlib import Path
from typing import IO, Any

from workcell.closing import Closing
from workcell.metrics import MetricThresholds
from workcell.record.chain import ChainKey
from workcell.record.entries import SessionInfo, TrialEnd, TrialStart
from workcell.record.errors import RecordError, StorageError, StoreError
from workcell.record.ids import new_id
from workcell.record.recovery import KnownEnd
from workcell.recording.frame_capture import CapturedFrames, FrameLayout
from workcell.recording.frame_ring import FrameRing
from workcell.recording.pipe_messages import raised_error, receive, send, start_writer
from workcell.recording.writer_answers import WriterAnswers
from workcell.recording.writer_death import close_for_dead_writer, death_error

ANSWER_TIMEOUT_S = 60.0
"""How long a call waits for the writer's answer before giving up on the writer."""
RING_CAPACITY = 512
"""Frames the ring holds (25 s of sim time at 20 Hz) before the recorder waits."""
CLOSE_TIMEOUT_S = 60.0
"""How long :meth:`StoreProcess.close` waits for the writer to finish what it was sent."""

Call = tuple[int | None, str, tuple[Any, ...], dict[str, Any]]


class StoreProcess(Closing):
    """A store opened for writing in a writer process; use :meth:`open`."""

    def __init__(
        self, path: Path, process: subprocess.Popen[bytes], key_file: Path | None = None
    ) -> None:
        self.path = path
        self._process = process
        self._key_file = key_file
        assert process.stdin is not None and process.stdout is not None
        self._requests: IO[bytes] = process.stdin
        self._answers: IO[bytes] = process.stdout
        self._ids = itertools.count()
        self._pending: list[Call] = []
        self._failure: Exception | None = None
        self._said = WriterAnswers(self._answers, self._call_failed)
        self._ring: FrameRing | None = None
        self._ring_layout: FrameLayout | None = None
        self._trial_numbers: dict[str, int] = {}
        self._trial_sessions: dict[str, str] = {}
        self._woken_at = 0
        """Ring position of the last wake-up message sent to the writer."""
        self.recovered: tuple[str, ...] = ()
        """Trials crash recovery closed when the writer opened the store."""

    @classmethod
    def open(
        cls,
        path: str | os.PathLike[str],
        *,
        poll_s: float | None = None,
        key_file: str | os.PathLike[str] | None = None,
    ) -> StoreProcess:
        """Start a writer process on the store at ``path`` (created if missing); it polls
        the frame ring every ``poll_s`` seconds (default
        :data:`~workcell.recording.store_worker.POLL_S`) and signs chain links with the key
        in ``key_file`` (if given).

        Raises what :meth:`Store.open` raises for a writer (a directory that does not
        exist, a file that is not a store, a store another process is writing, a full
        disk...).
        """
        path = Path(path)
        if poll_s is not None and not (math.isfinite(poll_s) and poll_s > 0):
            raise RecordError(f"poll_s: must be a positive number of seconds, got {poll_s!r}")
        if key_file is not None:
            key_file = Path(key_file).resolve()
            ChainKey.from_file(key_file)  # a bad key file is refused here, in one line
        process = start_writer(path, poll_s, key_file)
        store = cls(path, process, key_file)
        try:
            answer = receive(store._answers)
        except (EOFError, OSError):
            store._reap()
            raise store._died() from None
        if answer[0] == "error":
            store._reap()
            raise raised_error(answer[2], answer[3])
        store.recovered = tuple(answer[1])
        store._said.start()
        return store

    @property
    def pid(self) -> int:
        """The writer process's id."""
        return self._process.pid

    # ------------------------------------------------------------------ writing

    def create_session(self, info: SessionInfo) -> str:
        return str(self._call("create_session", info))

    def start_trial(self, session_id: str, start: TrialStart) -> str:
        """Sent at once, not waited for; the trial id is made here."""
        trial_id = new_id()
        self._queue("start_trial", (session_id, start), {"trial_id": trial_id})
        self._trial_numbers[trial_id] = len(self._trial_numbers)
        self._trial_sessions[trial_id] = session_id
        self._send_pending()  # its started_wall is now
        return trial_id

    def add_event(
        self,
        session_id: str,
        kind: str,
        payload: Mapping[str, object] | None = None,
        *,
        trial_id: str | None = None,
        t_sim: float | None = None,
        t_wall: float | None = None,
    ) -> None:
        """Sent with the next commit, stamped now (the event id is not returned)."""
        t_wall = time.time() if t_wall is None else t_wall
        keywords = {"trial_id": trial_id, "t_sim": t_sim, "t_wall": t_wall}
        self._queue("add_event", (session_id, kind, payload), keywords)

    def prepare_frames(self, layout: FrameLayout) -> None:
        """Make the frame ring for rows of ``layout`` now (waits for the writer), so that
        the first batch of a trial does not wait for it."""
        if self._failure is not None:
            raise self._failure
        if layout is not self._ring_layout and layout != self._ring_layout:
            self._attach_ring(layout)

    def add_captured_frames(self, trial_id: str, frames: CapturedFrames) -> int:
        """Copied into the ring at once (waiting only while it is full); the writer finds
        them at its next poll and formats, adds and commits them. Raises
        :class:`StorageError` when the writer has died."""
        self._check_writer()
        number = self._trial_numbers.get(trial_id)
        if number is None:
            raise RecordError(
                f"trial {trial_id} was not started through this store: start it first"
            )
        if frames.layout is not self._ring_layout:
            self.prepare_frames(frames.layout)  # the ring was made for another layout
        if self._pending:
            self._send_pending()  # the trial's start goes before its frames
        ring = self._ring
        assert ring is not None
        try:
            backlog = ring.publish(
                number, frames.rows, alive=self._writer_alive, full=self._wake_writer
            )
        except BrokenPipeError:
            raise self._failure or self._died() from None
        if backlog > ring.capacity // 2:
            self._wake_writer()  # more than half full: do not wait for the writer's poll
        return len(frames)

    def failure_pending(self) -> bool:
        """Whether the next call will raise a failure already known here: a call sent
        without waiting failed, or the writer's answer pipe closed (it died). Costs no
        system call: asked before every control period."""
        return self._failure is not None or self._said.closed

    def commit(self) -> None:
        """Send the events added since the last commit (frames are on their way already).
        Raises a failure the writer reported since the last call, or its death."""
        self._check_writer()
        if self._pending:
            self._send_pending()

    def end_trial(
        self, trial_id: str, end: TrialEnd, *, thresholds: MetricThresholds | None = None
    ) -> None:
        """Sent at once, not waited for: the writer closes the trial after its frames and
        says so (:meth:`trial_end_written`); a failure is raised by a later call."""
        if self._failure is not None:
            raise self._failure
        call_id = next(self._ids)
        self._said.expect_end(call_id, trial_id)
        self._pending.append((call_id, "end_trial", (trial_id, end), {"thresholds": thresholds}))
        self._send_pending()

    def trial_end_written(self, trial_id: str) -> bool:
        """Whether the writer has written the end of trial ``trial_id`` (a waited call
        answered after an :meth:`end_trial` means its answer has been read too)."""
        return self._said.end_written(trial_id)

    def end_session(self, session_id: str, status: str = "completed") -> None:
        self._call("end_session", session_id, status)

    def try_mark_interrupted(self, trial_id: str, reason: str = "storage_error") -> bool:
        """:meth:`try_interrupt_session` for the session of a trial started here."""
        session_id = self._trial_sessions.get(trial_id)
        return session_id is not None and self.try_interrupt_session(session_id, reason)

    def try_interrupt_session(self, session_id: str, reason: str = "storage_error") -> bool:
        """As :meth:`Store.try_interrupt_session`, by the writer; when the writer has died,
        this process opens the store and closes the session itself, with ``reason``.
        False when neither could."""
        self._pending.clear()  # what was not sent is not wanted after a failure
        if self._process.poll() is None:
            try:
                return bool(
                    self._call("try_interrupt_session", session_id, reason, after_failure=True)
                )
            except (StorageError, StoreError):
                if self._process.poll() is None:
                    return False
        return self._take_over(session_id, reason)

    def _take_over(self, session_id: str, reason: str) -> bool:
        """The writer is gone (and its lock with it): close the session in this process."""
        self._reap()
        detail = {"error": str(self._failure)} if self._failure is not None else {}
        end = KnownEnd(reason, detail)
        return close_for_dead_writer(self.path, session_id, end, self._key_file)

    def close(self) -> None:
        """Send what is pending, let the writer finish it, close the store and exit."""
        if self._process.returncode is None and self._failure is None:
            with contextlib.suppress(StorageError, StoreError, RecordError):
                self._send_pending()
        if self._process.returncode is None:
            with contextlib.suppress(OSError, ValueError):
                send(self._requests, "close")
        self._reap()
        if self._ring is not None:
            self._ring.unlink()
            self._ring.close()
            self._ring = None

    # ------------------------------------------------------------------ internals

    def _queue(
        self, method: str, args: tuple[Any, ...], keywords: dict[str, Any] | None = None
    ) -> None:
        if self._failure is not None:
            raise self._failure
        self._pending.append((None, method, args, keywords or {}))

    def _call(
        self,
        method: str,
        *args: Any,
        keywords: dict[str, Any] | None = None,
        after_failure: bool = False,
    ) -> Any:
        if self._failure is not None and not after_failure:
            raise self._failure
        call_id = next(self._ids)
        self._pending.append((call_id, method, args, keywords or {}))
        self._send_pending(check=not after_failure)
        try:
            answer = self._said.reply(ANSWER_TIMEOUT_S)
        except queue.Empty:
            raise self._died() from None
        if answer is None:
            raise self._died()
        if answer[0] == "error":
            raise raised_error(answer[2], answer[3])
        if self._failure is not None and not after_failure:
            raise self._failure  # an earlier call, run before this one, failed
        return answer[2]

    def _send_pending(self, *, check: bool = True, wake: bool = False) -> None:
        """Send the pending calls, with the ring position the writer is to write frames up
        to first; with ``wake`` even when no call is pending."""
        if check and self._failure is not None:
            raise self._failure
        calls, self._pending = self._pending, []
        if not calls and not wake:
            return
        position = 0 if self._ring is None else self._ring.published
        try:
            send(self._requests, (position, calls))
        except (OSError, ValueError):
            raise self._died() from None

    def _attach_ring(self, layout: FrameLayout) -> None:
        """A new ring for rows of ``layout``: the writer makes it (so that its file goes
        with the writer even if this process dies now), this process maps it and removes
        the file."""
        if self._ring is not None:
            self._call("commit")  # the old ring's frames are written first
            self._ring.close()
            self._ring = None
        path = self._call("create_ring", layout, RING_CAPACITY)
        try:
            ring = FrameRing.attach(path, layout.width, RING_CAPACITY)
            ring.unlink()
        except OSError as error:
            raise StorageError(
                f"store {self.path}: could not map the frame ring {path} "
                f"({error.strerror or error}); recording stopped"
            ) from None
        self._ring, self._ring_layout = ring, layout
        self._woken_at = 0

    def _wake_writer(self) -> None:
        """Tell the writer to take the ring's frames now (one short message), unless it
        has not yet taken those of the last such message."""
        ring = self._ring
        assert ring is not None
        if ring.consumed < self._woken_at:
            return
        self._woken_at = ring.published
        self._send_pending(wake=True)

    def _writer_alive(self) -> bool:
        """Whether the writer may still free ring space (running, and not failed)."""
        return self._failure is None and self._process.poll() is None

    def _check_writer(self) -> None:
        """Raise the writer's failure, or :class:`StorageError` if it has died (one
        ``waitpid``, no message)."""
        if self._failure is None and (self._said.closed or self._process.poll() is not None):
            self._died()
        if self._failure is not None:
            raise self._failure

    def _call_failed(self, error: Exception) -> None:
        """A call sent without waiting failed (told on the answers' thread): the next
        call raises ``error``, unless an earlier failure is raised already."""
        if self._failure is None:
            self._failure = error

    def _died(self) -> Exception:
        """The writer's death as the failure of this store (kept: later calls raise it)."""
        try:
            code: int | None = self._process.wait(timeout=1.0)
        except subprocess.TimeoutExpired:
            code = None
        if self._failure is None:
            self._failure = death_error(self.path, code)
        return self._failure

    def _reap(self) -> None:
        with contextlib.suppress(OSError, ValueError):
            self._requests.close()
        try:
            self._process.wait(timeout=CLOSE_TIMEOUT_S)
        except subprocess.TimeoutExpired:
            self._process.kill()
            self._process.wait()
        self._said.join(CLOSE_TIMEOUT_S)
        with contextlib.suppress(OSError, ValueError):
            self._answers.close()

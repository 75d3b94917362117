"""A store written by a child process, so that recording costs the simulation little.

The recorder hands over captured frames and events and goes on; the writer process (see
:mod:`workcell.record.store_worker`) formats, checksums, inserts and commits them on
another core. Frames and events are sent together at each :meth:`StoreProcess.commit`
(the recorder commits every 0.25 s of sim time), one write to the pipe per commit. Calls
whose answer the recorder needs (ids, the end of a trial or session) wait for it.

Guarantees are those of :class:`~workcell.record.store.Store`, kept across the pipe:

- calls are run in the order they are made, each commit's frames in one transaction;
- a failure of a call that was not waited for (disk full, a bad frame) is raised by the
  next call, as the same error class and message;
- if the recording process dies, however it dies, the writer still writes everything
  it was sent and then exits, leaving the running trial for crash recovery; what was
  not yet sent is at most one commit interval;
- the writer holds the store's writer lock, so no second writer opens the store until
  it has exited.
"""

from __future__ import annotations

import contextlib
import itertools
import os
import queue
import subprocess
import sys
import threading
from collections.abc import Mapping
from pathlib import Path
from types import TracebackType
from typing import IO, Any

from workcell.record.errors import RecordError, StorageError, StoreError
from workcell.record.frame_capture import CapturedFrames
from workcell.record.pipe_messages import receive, send
from workcell.record.records import SessionInfo, TrialEnd, TrialStart

ANSWER_TIMEOUT_S = 60.0
"""How long a call waits for the writer's answer before giving up on the writer."""
CLOSE_TIMEOUT_S = 60.0
"""How long :meth:`StoreProcess.close` waits for the writer to finish what it was sent."""

_ERRORS: dict[str, type[Exception]] = {
    "RecordError": RecordError,
    "StoreError": StoreError,
    "StorageError": StorageError,
}

Call = tuple[int | None, str, tuple[Any, ...], dict[str, Any]]


class StoreProcess:
    """A store opened for writing in a writer process; use :meth:`open`."""

    def __init__(self, path: Path, process: subprocess.Popen[bytes]) -> None:
        self.path = path
        self._process = process
        assert process.stdin is not None and process.stdout is not None
        self._requests: IO[bytes] = process.stdin
        self._answers: IO[bytes] = process.stdout
        self._ids = itertools.count()
        self._pending: list[Call] = []
        self._replies: queue.SimpleQueue[tuple[Any, ...] | None] = queue.SimpleQueue()
        self._failure: Exception | None = None
        self._reader: threading.Thread | None = None
        self.recovered: tuple[str, ...] = ()
        """Trials crash recovery closed when the writer opened the store."""

    @classmethod
    def open(cls, path: str | os.PathLike[str]) -> StoreProcess:
        """Start a writer process on the store at ``path`` (created if missing).

        Raises what :meth:`Store.open` raises for a writer (a directory that does not
        exist, a file that is not a store, a store another process is writing...).
        """
        path = Path(path)
        process = subprocess.Popen(
            [sys.executable, "-m", "workcell.record.store_worker", str(path)],
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            start_new_session=True,  # a terminal's Ctrl-C goes to the recording process only
        )
        store = cls(path, process)
        try:
            answer = receive(store._answers)
        except (EOFError, OSError):
            store._reap()
            raise store._died() from None
        if answer[0] == "error":
            store._reap()
            raise _error(answer[2], answer[3])
        store.recovered = tuple(answer[1])
        store._reader = threading.Thread(
            target=store._read_answers, name="store-writer-answers", daemon=True
        )
        store._reader.start()
        return store

    @property
    def pid(self) -> int:
        """The writer process's id."""
        return self._process.pid

    # ------------------------------------------------------------------ writing

    def create_session(self, info: SessionInfo) -> str:
        return str(self._call("create_session", info))

    def start_trial(self, session_id: str, start: TrialStart) -> str:
        return str(self._call("start_trial", session_id, start))

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
        """Sent with the next commit (the event id is not returned)."""
        keywords = {"trial_id": trial_id, "t_sim": t_sim, "t_wall": t_wall}
        self._queue("add_event", (session_id, kind, payload), keywords)

    def add_captured_frames(self, trial_id: str, frames: CapturedFrames) -> int:
        """Sent with the next commit; the writer formats and adds them."""
        self._queue("add_captured_frames", (trial_id, frames))
        return len(frames)

    def commit(self) -> None:
        """Send what was added since the last commit; the writer commits it in one
        transaction. Raises a failure the writer reported since the last call."""
        self._queue("commit", ())
        self._send_pending()

    def end_trial(self, trial_id: str, end: TrialEnd) -> None:
        self._call("end_trial", trial_id, end)

    def end_session(self, session_id: str, status: str = "completed") -> None:
        self._call("end_session", session_id, status)

    def try_mark_interrupted(self, trial_id: str, reason: str = "storage_error") -> bool:
        """As :meth:`Store.try_mark_interrupted`; False when the writer cannot answer."""
        self._pending.clear()  # what was not sent is not wanted after a failure
        try:
            return bool(self._call("try_mark_interrupted", trial_id, reason, after_failure=True))
        except (StorageError, StoreError):
            return False

    def close(self) -> None:
        """Send what is pending, let the writer finish it, close the store and exit."""
        if self._process.returncode is None and self._failure is None:
            with contextlib.suppress(StorageError, StoreError, RecordError):
                self._send_pending()
        if self._process.returncode is None:
            with contextlib.suppress(OSError, ValueError):
                send(self._requests, "close")
        self._reap()

    def __enter__(self) -> StoreProcess:
        return self

    def __exit__(
        self,
        kind: type[BaseException] | None,
        error: BaseException | None,
        traceback: TracebackType | None,
    ) -> None:
        self.close()

    # ------------------------------------------------------------------ internals

    def _queue(
        self, method: str, args: tuple[Any, ...], keywords: dict[str, Any] | None = None
    ) -> None:
        if self._failure is not None:
            raise self._failure
        self._pending.append((None, method, args, keywords or {}))

    def _call(self, method: str, *args: Any, after_failure: bool = False) -> Any:
        if self._failure is not None and not after_failure:
            raise self._failure
        call_id = next(self._ids)
        self._pending.append((call_id, method, args, {}))
        self._send_pending(check=not after_failure)
        try:
            answer = self._replies.get(timeout=ANSWER_TIMEOUT_S)
        except queue.Empty:
            raise self._died() from None
        if answer is None:
            raise self._died()
        if answer[0] == "error":
            raise _error(answer[2], answer[3])
        if self._failure is not None and not after_failure:
            raise self._failure  # an earlier call, run before this one, failed
        return answer[2]

    def _send_pending(self, *, check: bool = True) -> None:
        if check and self._failure is not None:
            raise self._failure
        calls, self._pending = self._pending, []
        if not calls:
            return
        try:
            send(self._requests, calls)
        except (OSError, ValueError):
            raise self._died() from None

    def _read_answers(self) -> None:
        """The reader thread: answers to waiting calls, failures of the others."""
        while True:
            try:
                answer = receive(self._answers)
            except (EOFError, OSError, ValueError):
                self._replies.put(None)
                return
            if answer[1] is None:  # a call sent without waiting failed
                if self._failure is None:
                    self._failure = _error(answer[2], answer[3])
            else:
                self._replies.put(answer)

    def _died(self) -> StorageError:
        code = self._process.poll()
        return StorageError(
            f"store {self.path}: the store writer process "
            f"{'is not answering' if code is None else f'exited (code {code})'}; recording "
            "stopped — everything it committed is intact; open the store again to recover "
            "the running trial"
        )

    def _reap(self) -> None:
        with contextlib.suppress(OSError, ValueError):
            self._requests.close()
        try:
            self._process.wait(timeout=CLOSE_TIMEOUT_S)
        except subprocess.TimeoutExpired:
            self._process.kill()
            self._process.wait()
        if self._reader is not None:
            self._reader.join(timeout=CLOSE_TIMEOUT_S)
        with contextlib.suppress(OSError, ValueError):
            self._answers.close()


def _error(kind: str, text: str) -> Exception:
    return _ERRORS.get(kind, StorageError)(text)

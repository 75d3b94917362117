"""The store writer process: owns one store opened for writing and runs what a
:class:`~workcell.recording.store_process.StoreProcess` sends it, in order.

Run as ``python -m workcell.recording.store_worker STORE [--poll S] [--key FILE]`` by
:class:`StoreProcess` only; it computes the hash-chain links (signed with the key in
``FILE``) as it closes trials and sessions.
Frames arrive through a shared-memory :class:`~workcell.recording.frame_ring.FrameRing`,
polled every :data:`POLL_S` and committed as they come. Calls arrive on stdin and answers
leave on stdout (see :mod:`workcell.recording.pipe_messages`):

- ``(position, calls)``: first the frames published before ring position ``position`` are
  written, then each call ``(call_id, method, args, keywords)`` runs as
  ``Store.<method>(*args, **keywords)``. A call with an id is answered
  ``("ok", call_id, result)`` or ``("error", call_id, kind, text)``; a call sent without
  waiting has ``call_id`` None and is answered only when it fails (the first failure).
  ``create_ring`` makes the ring (this process owns its file) and answers its path;
  trials are numbered in the ring in the order of their ``start_trial`` calls.
- ``"close"`` or the end of stdin: write every complete frame in the ring, close the
  store, exit.

The end of stdin is also how the process learns that the recording process died (even by
SIGKILL): everything published before is written, the running trial stays open, and the
next writer to open the store closes it as ``interrupted``/``crash_recovered``.
"""

from __future__ import annotations

import argparse
import signal
import sys
import time
from pathlib import Path
from typing import IO, Any

from workcell.errors import WorkcellError
from workcell.record.chain import ChainKey
from workcell.record.errors import StorageError
from workcell.recording.frame_capture import CapturedFrames, FrameLayout
from workcell.recording.frame_ring import FrameRing
from workcell.recording.in_process import InProcessStore
from workcell.recording.pipe_messages import MessageReader, send

POLL_S = 0.05
"""How often the ring is polled for new frames when no call arrives. Frames in the ring
are safe from the recording process's death (this process writes them all when it sees
the end of stdin); the interval bounds only what the death of this process itself would
lose, in wall time. Longer polls commit more frames at once (every poll and every commit has
a fixed cost): at 50 ms the writer spends 70 µs of CPU a recorded frame, 135 µs at 5 ms
(bench/record.py). The recording process wakes the writer early when the ring is half
full."""
WAIT_S = 0.0005
"""How long to wait for a frame published but not yet completely visible."""
INCOMPLETE_LIMIT_S = 10.0
"""A frame still incomplete after this long means the ring is damaged."""

STORE_CALLS = frozenset(
    {
        "create_session",
        "start_trial",
        "add_event",
        "commit",
        "end_trial",
        "end_session",
        "try_mark_interrupted",
        "try_interrupt_session",
    }
)
"""The Store methods a recording process may call."""


class Writer:
    """Runs calls and writes ring frames into ``store``, reporting on ``answers``."""

    def __init__(self, store: InProcessStore, answers: IO[bytes], poll_s: float = POLL_S) -> None:
        self.store = store
        self.answers = answers
        self.poll_s = poll_s
        self.ring: FrameRing | None = None
        self.layout: FrameLayout | None = None
        self.trials: list[str] = []
        """Trial ids by their number in the ring."""
        self.failed = False

    def serve(self, requests: IO[bytes]) -> None:
        """Until ``"close"`` or the end of ``requests``: messages as they come, the ring's
        frames every ``poll_s`` (one thread; the timer is this process's own, so the
        recording process does not have to wake it, except when the ring fills up)."""
        inbox = MessageReader(requests.fileno())
        try:
            while True:
                messages = inbox.wait(self.poll_s)
                if not messages:
                    self.write_frames()
                for message in messages:
                    if message is None or message == "close":
                        self.write_frames()
                        return
                    position, calls = message
                    self.write_frames(upto=position)
                    for call in calls:
                        self.run(*call)
        finally:
            self._drop_ring()

    def run(self, call_id: int | None, method: str, args: Any, keywords: Any) -> None:
        try:
            result = self._dispatch(method, args, keywords)
        except WorkcellError as error:
            self.report(call_id, error)
            return
        if call_id is not None:
            send(self.answers, ("ok", call_id, result))

    def report(self, call_id: int | None, error: WorkcellError) -> None:
        if call_id is not None or not self.failed:
            send(self.answers, ("error", call_id, type(error).__name__, str(error)))
        self.failed = self.failed or call_id is None

    def write_frames(self, upto: int | None = None) -> None:
        """Write and commit the ring's complete frames (all up to ``upto`` if given)."""
        ring, layout = self.ring, self.layout
        if ring is None or layout is None:
            return
        deadline = time.monotonic() + INCOMPLETE_LIMIT_S
        while True:
            for number, rows in ring.take(upto, trials_known=len(self.trials)):
                if self.failed:
                    continue  # recording stopped: the frames are dropped, the ring freed
                try:
                    self.store.add_captured_frames(
                        self.trials[number], CapturedFrames(layout, rows)
                    )
                    self.store.commit()
                except WorkcellError as error:
                    self.report(None, error)
            if upto is None or ring.consumed >= upto:
                return
            if time.monotonic() > deadline:
                self.report(
                    None,
                    StorageError(
                        f"store {self.store.path}: frame {ring.consumed} in the frame ring "
                        "stayed incomplete; recording stopped"
                    ),
                )
                self._drop_ring()  # nothing more is read from it
                return
            time.sleep(WAIT_S)

    def _drop_ring(self) -> None:
        """Unmap the ring and remove its file (the recording side removes it as soon as it
        has mapped it; this covers a recording process that died before)."""
        if self.ring is not None:
            self.ring.unlink()
            self.ring.close()
            self.ring = None

    def _dispatch(self, method: str, args: Any, keywords: Any) -> Any:
        if method == "create_ring":
            layout, capacity = args
            self._drop_ring()
            try:
                self.ring = FrameRing.create(layout.width, capacity)
            except OSError as error:
                raise StorageError(
                    f"store {self.store.path}: could not create the shared-memory frame ring "
                    f"({error.strerror or error}); recording stopped — free memory or disk "
                    "space"
                ) from None
            self.layout = layout
            return str(self.ring.path)
        if method not in STORE_CALLS:
            raise WorkcellError(f"store writer: unknown call {method!r}")
        if method != "start_trial":
            return getattr(self.store, method)(*args, **keywords)
        try:
            trial_id = self.store.start_trial(*args, **keywords)
        finally:  # numbered in the order started, failed or not
            self.trials.append(keywords["trial_id"])
        return trial_id


def main(argv: list[str]) -> int:
    # Ctrl-C is for the recording process, which ends the trial and then closes this one.
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    requests, answers = sys.stdin.buffer, sys.stdout.buffer
    parser = argparse.ArgumentParser(prog="workcell.recording.store_worker")
    parser.add_argument("store")
    parser.add_argument("--poll", type=float, default=POLL_S)
    parser.add_argument("--key", type=Path)
    args = parser.parse_args(argv[1:])
    try:
        key = None if args.key is None else ChainKey.from_file(args.key)
        store = InProcessStore.open(args.store, writer=True, key=key)
    except WorkcellError as error:
        send(answers, ("error", None, type(error).__name__, str(error)))
        return 1
    poll_s = args.poll
    with store:
        send(answers, ("ready", store.recovered))
        Writer(store, answers, poll_s).serve(requests)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))

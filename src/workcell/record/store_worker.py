"""The store writer process: owns one store opened for writing and runs the calls a
:class:`~workcell.record.store_process.StoreProcess` sends it, in order.

Run as ``python -m workcell.record.store_worker STORE`` by :class:`StoreProcess` only.
Calls arrive on stdin, answers leave on stdout (see :mod:`workcell.record.pipe_messages`):

- a list of calls ``(call_id, method, args, keywords)``, each run as
  ``Store.<method>(*args, **keywords)`` in order. A call with an id is answered
  ``("ok", call_id, result)`` or ``("error", call_id, kind, text)``; a call sent without
  waiting has ``call_id`` None and is answered only when it fails (its first failure).
- ``"close"`` or the end of stdin: commit what was received, close the store, exit.

The end of stdin is also how the process learns that the recording process died (even by
SIGKILL): everything sent before is written, the running trial stays open, and the next
writer to open the store closes it as ``interrupted``/``crash_recovered``.
"""

from __future__ import annotations

import signal
import sys
from typing import IO, Any

from workcell.errors import WorkcellError
from workcell.record.pipe_messages import receive, send
from workcell.record.store import Store

CALLS = frozenset(
    {
        "create_session",
        "start_trial",
        "add_event",
        "add_captured_frames",
        "commit",
        "end_trial",
        "end_session",
        "try_mark_interrupted",
    }
)
"""The Store methods a recording process may call."""


def serve(store: Store, requests: IO[bytes], answers: IO[bytes]) -> None:
    """Run calls until ``"close"`` or the end of ``requests``."""
    failed = False
    while True:
        try:
            calls = receive(requests)
        except EOFError:
            return
        if calls == "close":
            return
        for call_id, method, args, keywords in calls:
            try:
                if method not in CALLS:
                    raise WorkcellError(f"store writer: unknown call {method!r}")
                result: Any = getattr(store, method)(*args, **keywords)
            except WorkcellError as error:
                if call_id is not None or not failed:
                    send(answers, ("error", call_id, type(error).__name__, str(error)))
                failed = failed or call_id is None
                continue
            if call_id is not None:
                send(answers, ("ok", call_id, result))


def main(argv: list[str]) -> int:
    # Ctrl-C is for the recording process, which ends the trial and then closes this one.
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    requests, answers = sys.stdin.buffer, sys.stdout.buffer
    try:
        store = Store.open(argv[1], writer=True)
    except WorkcellError as error:
        send(answers, ("error", None, type(error).__name__, str(error)))
        return 1
    with store:
        send(answers, ("ready", store.recovered))
        serve(store, requests, answers)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))

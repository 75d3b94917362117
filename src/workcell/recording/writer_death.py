"""When the store writer process dies under a recording process: how to say it, and how
the recording process closes its session itself (the writer's lock died with it)."""

from __future__ import annotations

import signal
from pathlib import Path

from workcell.errors import WorkcellError
from workcell.record.chain import ChainKey
from workcell.record.errors import StorageError
from workcell.record.recovery import KnownEnd
from workcell.record.store import Store


def death_error(store: Path, code: int | None) -> StorageError:
    """The failure of a writer that exited with ``code`` (negative: killed by that
    signal; None: alive but not answering)."""
    if code is None:
        how = "is not answering"
    elif code < 0:
        how = f"was killed ({signal.Signals(-code).name})"
    else:
        how = f"exited (status {code})"
    return StorageError(
        f"store {store}: the store writer process {how}; recording stopped — everything it "
        "committed is intact"
    )


def close_for_dead_writer(
    store: Path,
    session_id: str,
    end: KnownEnd,
    key_file: Path | None,
) -> bool:
    """Open the store in this process and close ``session_id`` as ``end`` says (its
    running trial ``interrupted`` with that reason, the session ``interrupted``); whether
    it is closed now. Crash recovery does it, with the reason this process knows."""
    try:
        key = None if key_file is None else ChainKey.from_file(key_file)
        with Store.open(store, writer=True, key=key, known={session_id: end}) as opened:
            return any(
                s.session_id == session_id and s.status == "interrupted" for s in opened.sessions()
            )
    except WorkcellError:
        return False

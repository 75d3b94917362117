"""Write transactions of a store, and what happens when the disk refuses a write.

The store runs with ``synchronous=NORMAL`` (WAL mode): a commit is durable against the
death of the process at once, but against a power cut of the machine only once SQLite has
synced the log (at its next checkpoint): a power cut can lose the last commits (never
corrupt the file). Durable writes (a trial's or a session's end, a reviewer's
annotation) run with ``synchronous=FULL`` instead: their commit syncs the log, so once
they return, the trial's end and everything before it survive a power cut.
"""

from __future__ import annotations

import contextlib
import sqlite3
from collections.abc import Callable, Iterator
from pathlib import Path

from workcell.record.diagnose import storage_advice
from workcell.record.errors import RecordError, StorageError


class WriteGuard:
    """Runs each write of a store as a savepoint inside the open transaction.

    A constraint violation (a caller's mistake) undoes only that write and raises
    :class:`RecordError`. Any other SQLite or OS error rolls the whole transaction back,
    stops all further writes, and raises :class:`StorageError` with one line naming the
    store, the cause and what to do. ``resync`` is called after every rollback so the
    store's counters match what is committed.
    """

    def __init__(self, path: Path, conn: sqlite3.Connection, resync: Callable[[], None]) -> None:
        self._path = path
        self._conn = conn
        self._resync = resync
        self.failure: StorageError | None = None

    def require(self) -> None:
        if self.failure is not None:
            raise StorageError(f"{self.failure} (no further writes)")

    @contextlib.contextmanager
    def write(self, *, commit: bool = True, durable: bool = False) -> Iterator[sqlite3.Connection]:
        """A write inside the open transaction (one is begun if needed), committed unless
        ``commit`` is False. ``durable``: commit what is pending first, then run this write
        in its own transaction that syncs the log as it commits (see the module)."""
        self.require()
        conn = self._conn
        try:
            if durable:
                if conn.in_transaction:
                    conn.execute("COMMIT")
                conn.execute("PRAGMA synchronous = FULL")
            if not conn.in_transaction:
                conn.execute("BEGIN IMMEDIATE")
            conn.execute("SAVEPOINT write")
        except (sqlite3.Error, OSError) as error:
            self._normal(durable)
            raise self.fail(error) from error
        try:
            yield conn
            conn.execute("RELEASE write")
            if commit or durable:
                conn.execute("COMMIT")
        except sqlite3.IntegrityError as error:
            self._undo_write()
            raise RecordError(f"store {self._path}: {error}") from None
        except (sqlite3.Error, OSError) as error:
            raise self.fail(error) from error
        except BaseException:
            self._undo_write()
            raise
        finally:
            self._normal(durable)

    def _normal(self, durable: bool) -> None:
        """Back to ``synchronous=NORMAL`` after a durable write (outside a transaction)."""
        if durable and not self._conn.in_transaction:
            with contextlib.suppress(sqlite3.Error):
                self._conn.execute("PRAGMA synchronous = NORMAL")

    def commit(self) -> None:
        self.require()
        if self._conn.in_transaction:
            try:
                self._conn.execute("COMMIT")
            except (sqlite3.Error, OSError) as error:
                raise self.fail(error) from error

    def fail(self, error: BaseException) -> StorageError:
        """Roll back, stop writing, and describe the failure in one line."""
        self.rollback()
        cause = str(error).strip() or type(error).__name__
        self.failure = StorageError(
            f"store {self._path}: could not write ({cause}); recording stopped — "
            f"{storage_advice(self._path, cause)}; everything committed before is intact"
        )
        return self.failure

    def rollback(self) -> None:
        """Roll back the open transaction (if any) and resync the store's counters."""
        with contextlib.suppress(sqlite3.Error):
            if self._conn.in_transaction:
                self._conn.execute("ROLLBACK")
        with contextlib.suppress(sqlite3.Error):
            self._resync()

    def _undo_write(self) -> None:
        with contextlib.suppress(sqlite3.Error):
            self._conn.execute("ROLLBACK TO write")
            self._conn.execute("RELEASE write")

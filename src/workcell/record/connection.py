"""Opening a store file: the writer lock, SQLite settings and the schema check.

A writer holds an exclusive ``flock`` on ``<store>.lock`` for as long as it is open; the
operating system releases it when the process dies, however it dies. Readers take no lock
and never write: in WAL mode they see every committed transaction while a writer writes.
"""

from __future__ import annotations

import contextlib
import fcntl
import os
import sqlite3
import time
import urllib.parse
from collections.abc import Iterator
from pathlib import Path

from workcell import __version__
from workcell.record import chain_tip
from workcell.record.chain_key import ChainKey
from workcell.record.diagnose import storage_advice
from workcell.record.errors import StorageError, StoreError
from workcell.record.ids import new_id
from workcell.record.migrate import MIGRATION_NOTES, MIGRATIONS, migrate
from workcell.record.schema import (
    APPLICATION_ID,
    FRAME_BLOCKS_SQL,
    LAYOUTS,
    SCHEMA_VERSION,
    schema_statements,
)

BUSY_TIMEOUT_MS = 5000
LOCK_ATTEMPTS = 100
LOCK_RETRY_S = 0.02


def lock_path(path: Path) -> Path:
    return path.with_name(path.name + ".lock")


class WriterLock:
    """The exclusive writer lock of one store (released by :meth:`release` or by death).

    :meth:`release` removes the lock file while it still holds the lock, so that a clean
    close leaves only the store. A writer that was waiting on that file's lock then holds a
    file no longer there: it sees so (the path names another file, or none) and locks the
    file now at the path, so two writers never hold locks at once."""

    def __init__(self, path: Path) -> None:
        if not path.parent.is_dir():
            raise StoreError(f"cannot open store {path}: directory {path.parent} does not exist")
        self._path = lock_path(path)
        self._fd: int | None = None
        for attempt in range(LOCK_ATTEMPTS):
            try:
                fd = os.open(self._path, os.O_RDWR | os.O_CREAT, 0o644)
            except OSError as error:
                raise StoreError(
                    f"cannot open store {path} for writing: {error.strerror}"
                ) from None
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except BlockingIOError:
                holder = os.pread(fd, 32, 0).decode(errors="replace").strip()
                os.close(fd)
                if attempt == LOCK_ATTEMPTS - 1:
                    raise StoreError(
                        f"store {path} is already open for writing by another process"
                        f"{f' (pid {holder})' if holder else ''}; close that recorder first "
                        "or record to another store"
                    ) from None
                time.sleep(LOCK_RETRY_S)
                continue
            if _is_at(fd, self._path):
                self._fd = fd
                break
            os.close(fd)  # the writer before removed this file as it closed: lock the new one
        if self._fd is None:
            raise StoreError(f"store {path}: its lock file kept changing; try again")
        with contextlib.suppress(OSError):  # the pid is a courtesy; a full disk refuses it
            os.ftruncate(self._fd, 0)
            os.pwrite(self._fd, f"{os.getpid()}\n".encode(), 0)

    def release(self) -> None:
        if self._fd is not None:
            with contextlib.suppress(OSError):
                if _is_at(self._fd, self._path):
                    self._path.unlink()  # while locked: see the class docstring
            os.close(self._fd)  # closing the only descriptor releases the flock
            self._fd = None


def _is_at(fd: int, path: Path) -> bool:
    """Whether ``path`` names the file open as ``fd``."""
    try:
        named = os.stat(path)
    except FileNotFoundError:
        return False
    opened = os.fstat(fd)
    return (named.st_dev, named.st_ino) == (opened.st_dev, opened.st_ino)


def writer_active(path: Path) -> bool:
    """True when some process holds the writer lock of the store at ``path``."""
    try:
        fd = os.open(lock_path(path), os.O_RDONLY)
    except FileNotFoundError:
        return False
    try:
        fcntl.flock(fd, fcntl.LOCK_SH | fcntl.LOCK_NB)
    except BlockingIOError:
        return True
    finally:
        os.close(fd)  # also drops the shared lock taken to probe
    return False


def connect(
    path: Path, *, writer: bool, check: bool = False, key: ChainKey | None = None
) -> sqlite3.Connection:
    """A connection to the store at ``path`` with the schema checked (created when a writer
    opens a new file); with ``check``, SQLite's quick integrity check first (a damaged
    file raises :class:`StoreError` instead of being read). Transactions are explicit
    (``isolation_level=None``). A writer migrating an older store signs its chain tip with
    ``key``."""
    if not writer and not path.is_file():
        raise StoreError(f"no store at {path}: give the path of a store a recorder wrote")
    if writer:
        conn = sqlite3.connect(path, isolation_level=None, timeout=BUSY_TIMEOUT_MS / 1000)
    else:
        uri = f"file:{urllib.parse.quote(str(path.resolve()))}?mode=ro"
        conn = sqlite3.connect(uri, uri=True, isolation_level=None)
    try:
        conn.execute(f"PRAGMA busy_timeout = {BUSY_TIMEOUT_MS}")
        if check:
            quick_check(conn, path)
        _check_or_create(conn, path, writer=writer, key=key)
        conn.execute("PRAGMA foreign_keys = ON")
        conn.execute("PRAGMA synchronous = NORMAL")
        if not writer:
            conn.execute("PRAGMA query_only = ON")
    except sqlite3.DatabaseError as error:
        conn.close()
        if is_damage(error) and "not a database" not in str(error):
            raise damaged(path, error) from None
        if _storage_trouble(error):
            cause = str(error).strip()
            raise StorageError(
                f"store {path}: could not {'write' if writer else 'read'} it ({cause}) — "
                f"{storage_advice(path, cause)}"
            ) from None
        raise StoreError(f"{path} is not a Workcell store ({error})") from None
    except BaseException:
        conn.close()
        raise
    return conn


def quick_check(conn: sqlite3.Connection, path: Path) -> None:
    """Raise :class:`StoreError` when SQLite's quick check finds the file damaged."""
    (first,) = conn.execute("PRAGMA quick_check(1)").fetchone()
    if first != "ok":
        raise StoreError(
            f"store {path} is damaged (SQLite's integrity check: {' '.join(first.split())}); "
            "nothing was read from it or written to it: restore it from a copy"
        )


def check_intact(path: Path) -> None:
    """Raise :class:`StoreError` when the existing store file at ``path`` is damaged
    (SQLite's quick check, read-only; nothing else about the store is checked)."""
    uri = f"file:{urllib.parse.quote(str(path.resolve()))}?mode=ro"
    try:
        with contextlib.closing(sqlite3.connect(uri, uri=True)) as conn:
            quick_check(conn, path)
    except sqlite3.DatabaseError as error:
        if is_damage(error):
            raise damaged(path, error) from None
        raise StoreError(f"cannot read store {path} ({str(error).strip()})") from None


def is_damage(error: sqlite3.DatabaseError) -> bool:
    """Whether SQLite failed because the file is damaged or not a database at all."""
    name = getattr(error, "sqlite_errorname", "") or ""
    return name.startswith(("SQLITE_CORRUPT", "SQLITE_NOTADB"))


def damaged(path: Path, error: sqlite3.DatabaseError) -> StoreError:
    """The one-line error of a store SQLite found damaged while reading or writing it."""
    return StoreError(
        f"store {path} is damaged ({str(error).strip()}); it cannot be read as a store: "
        "restore it from a copy"
    )


@contextlib.contextmanager
def damage_as_store_error(path: Path) -> Iterator[None]:
    """Within: a damaged store's sqlite3 error becomes :func:`damaged`'s StoreError."""
    try:
        yield
    except sqlite3.DatabaseError as error:
        if is_damage(error):
            raise damaged(path, error) from None
        raise


def _storage_trouble(error: sqlite3.DatabaseError) -> bool:
    """Whether SQLite failed for the disk (full, I/O, cannot open) rather than the file."""
    name = getattr(error, "sqlite_errorname", "") or ""
    return name.startswith(("SQLITE_FULL", "SQLITE_IOERR", "SQLITE_CANTOPEN", "SQLITE_READONLY"))


def _check_or_create(
    conn: sqlite3.Connection, path: Path, *, writer: bool, key: ChainKey | None
) -> None:
    application_id = conn.execute("PRAGMA application_id").fetchone()[0]
    version = conn.execute("PRAGMA user_version").fetchone()[0]
    n_tables = conn.execute("SELECT count(*) FROM sqlite_schema").fetchone()[0]
    if application_id == 0 and version == 0 and n_tables == 0:
        if not writer:
            raise StoreError(f"{path} is an empty database, not a Workcell store")
        _create(conn)
        return
    if application_id != APPLICATION_ID:
        raise StoreError(
            f"{path} is an SQLite database but not a Workcell store "
            f"(application_id {application_id:#x}, expected {APPLICATION_ID:#x})"
        )
    if version > SCHEMA_VERSION:
        raise StoreError(
            f"store {path} was written by schema version {version}; this Workcell "
            f"({__version__}) reads up to {SCHEMA_VERSION} — upgrade Workcell"
        )
    if version < SCHEMA_VERSION and not (writer and version in MIGRATIONS):
        raise StoreError(
            f"store {path} has schema version {version}, which this Workcell reads only "
            f"after migrating it to version {SCHEMA_VERSION}"
            + (
                f" ({MIGRATION_NOTES[version]}): open it for writing once, e.g. "
                f"'workcell verify --recover --store {path}'; every row is kept"
                if version in MIGRATIONS
                else ""
            )
        )
    mode = conn.execute("PRAGMA journal_mode").fetchone()[0]
    if mode != "wal":
        raise StoreError(
            f"store {path} is not in WAL mode (journal_mode {mode}); it was "
            "not written by Workcell or was altered"
        )
    tables = {r[0] for r in conn.execute("SELECT name FROM sqlite_schema WHERE type='table'")}
    required = (
        {"meta", *(layout.name for layout in LAYOUTS)}
        | ({"chain"} if version >= 2 else set())
        | ({"chain_roots"} if version >= 4 else set())
    )
    missing = sorted(required - tables)
    if missing:
        raise StoreError(f"store {path} lacks tables {', '.join(missing)}; it was altered")
    if writer and "frame_blocks" not in tables:  # a store from before frame blocks
        conn.execute(FRAME_BLOCKS_SQL)
    if version < SCHEMA_VERSION:
        migrate(conn, version, key, str(path))


def _create(conn: sqlite3.Connection) -> None:
    if conn.execute("PRAGMA journal_mode = WAL").fetchone()[0] != "wal":
        raise StoreError("SQLite refused WAL mode; put the store on a local file system")
    conn.execute("BEGIN IMMEDIATE")
    try:
        for statement in schema_statements():
            conn.execute(statement)
        store_id = new_id()
        conn.executemany(
            "INSERT INTO meta (key, value) VALUES (?, ?)",
            [
                ("schema_version", str(SCHEMA_VERSION)),
                ("software_version", __version__),
                ("store_id", store_id),
                ("created_wall", repr(time.time())),
            ],
        )
        chain_tip.declare_root(conn, chain_tip.store_root(store_id), store_id, chain_tip.CREATED)
        conn.execute("COMMIT")
    except BaseException:
        with contextlib.suppress(sqlite3.Error):
            conn.execute("ROLLBACK")
        raise

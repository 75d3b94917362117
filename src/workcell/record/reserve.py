"""Headroom on the disk, so that a trial can still be closed when the disk fills up.

When the disk is full, SQLite cannot append even the few pages that record a trial's end
(its outcome, the ``interruption`` event, the session's end and their hash-chain links),
and the trial would stay open until a later writer found it. So a writer keeps a file of
:data:`RESERVE_BYTES` beside the store, ``<store>.reserve``, its blocks allocated on the
disk. When a write fails for lack of space the store deletes that file, which gives back
exactly that much room, and writes the trial's and the session's end into it. The next
writer makes the file again, and refuses to open the store (before anything is recorded)
while the disk has no room for it.
"""

from __future__ import annotations

import contextlib
import errno
import os
from pathlib import Path

from workcell.record.diagnose import storage_advice
from workcell.record.errors import StorageError

RESERVE_BYTES = 256 * 1024
"""Room kept for closing a trial and its session on a full disk: eight times what the
closing transaction appends to the write-ahead log (8 pages, 33 KB, whatever the trial's
length; tests/record/test_disk_full.py measures it)."""


def reserve_path(store: Path) -> Path:
    return store.with_name(store.name + ".reserve")


class Reserve:
    """The headroom file of the store at ``store``."""

    def __init__(self, store: Path, size: int = RESERVE_BYTES) -> None:
        self.store = store
        self.path = reserve_path(store)
        self.size = size

    def ensure(self) -> None:
        """Make the file (all its blocks allocated) unless it is there already. Raises
        :class:`StorageError` naming the full disk when there is no room for it."""
        with contextlib.suppress(OSError):
            if self.path.stat().st_size >= self.size:
                return
        try:
            fd = os.open(self.path, os.O_WRONLY | os.O_CREAT, 0o644)
            try:
                _allocate(fd, self.size)
                os.fsync(fd)
            finally:
                os.close(fd)
        except OSError as error:
            with contextlib.suppress(OSError):
                self.path.unlink()
            raise self._refusal(error) from None

    def _refusal(self, error: OSError) -> StorageError:
        folder = self.store.parent
        if error.errno in (errno.ENOSPC, errno.EDQUOT, errno.EFBIG):
            free = ""
            with contextlib.suppress(OSError):
                stat = os.statvfs(folder)
                free = f" ({stat.f_bavail * stat.f_frsize // 1024} KiB free)"
            where = f"the disk holding {folder} is full{free}"
            if error.errno == errno.EFBIG:
                where = storage_advice(self.store, "file too large")
            return StorageError(
                f"store {self.store}: {where}: a writer keeps {self.size // 1024} KiB free "
                "beside the store to close a trial when the disk fills up — free space, then "
                "try again; nothing was recorded"
            )
        return StorageError(
            f"store {self.store}: cannot make {self.path} ({error.strerror or error}) — check "
            f"the permissions of {folder} and its file system; nothing was recorded"
        )

    def missing_room(self) -> StorageError | None:
        """:meth:`ensure`, returning its error instead of raising it."""
        try:
            self.ensure()
        except StorageError as error:
            return error
        return None

    def release(self) -> bool:
        """Delete the file, giving its room back; whether there was one."""
        try:
            self.path.unlink()
        except OSError:
            return False
        return True


def _allocate(fd: int, size: int) -> None:
    """Allocate ``size`` bytes of ``fd`` on the disk (not a sparse file)."""
    try:
        os.posix_fallocate(fd, 0, size)
    except OSError as error:
        if error.errno not in (errno.EOPNOTSUPP, errno.EINVAL):
            raise
        block = b"\0" * 65536  # a file system without fallocate: write the zeros
        for offset in range(0, size, len(block)):
            os.pwrite(fd, block[: size - offset], offset)

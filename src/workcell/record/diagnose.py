"""Why a write to a store failed, in words: SQLite reports a full disk and a file-size limit
alike as a 'disk I/O error', so look at the file system and the process's limits."""

from __future__ import annotations

import os
import resource
from pathlib import Path

LOW_SPACE_BYTES = 1 << 20
"""Less free space than this on the store's file system counts as a full disk."""
NEAR_LIMIT_BYTES = 1 << 16


def storage_advice(path: Path, cause: str) -> str:
    """What most likely went wrong with writing the store at ``path``, and what to do."""
    try:
        stat = os.statvfs(path.parent)
        if stat.f_bavail * stat.f_frsize < LOW_SPACE_BYTES:
            return f"the disk holding {path.parent} is full: free space and start a new session"
    except OSError:
        pass
    limit, _ = resource.getrlimit(resource.RLIMIT_FSIZE)
    if limit != resource.RLIM_INFINITY:
        sizes = []
        for suffix in ("", "-wal", "-shm"):
            try:
                sizes.append(path.with_name(path.name + suffix).stat().st_size)
            except OSError:
                continue
        if any(size >= limit - NEAR_LIMIT_BYTES for size in sizes):
            return (
                f"a store file reached this process's file-size limit ({limit} bytes): "
                "raise the limit (ulimit -f) and start a new session"
            )
    if "full" in cause:
        return "the disk is full: free space and start a new session"
    return "check free disk space and the file system, then start a new session"

"""A ring of captured frame rows in shared memory, from a recording process to its writer.

The recording process copies each batch of captured rows into the ring and moves a
counter; it makes no system call and builds no Python object per frame. The writer
process polls the ring, takes the rows in order and moves its own counter back. Each row
carries the number of the trial it belongs to and a CRC-32 of its contents, so the writer
takes a row only once it is completely visible, whatever the CPU's memory ordering.

Layout of the mapped file: the published count (int64) at byte 0, the consumed count
(int64) at byte 64 (another cache line), then ``capacity`` rows of ``width + 2`` float64:
the trial number, the ``width`` values of a :class:`~workcell.record.frame_capture.
FrameLayout` row, and the CRC.
"""

from __future__ import annotations

import mmap
import os
import tempfile
import time
import zlib
from collections.abc import Callable
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

_HEADER_BYTES = 128
_PUBLISHED, _CONSUMED = 0, 8  # int64 slots of the header
SPACE_WAIT_S = 0.0005
"""How long the recording process sleeps while the ring is full."""


def ring_folder() -> str | None:
    """Where ring files go: shared memory when the system has it."""
    return "/dev/shm" if os.path.isdir("/dev/shm") else None


class FrameRing:
    """One end of a ring: :meth:`create` (recording side) or :meth:`attach` (writer)."""

    def __init__(self, path: Path, width: int, capacity: int, file: int) -> None:
        self.path = path
        self.width = width
        self.capacity = capacity
        self._map = mmap.mmap(file, _HEADER_BYTES + capacity * (width + 2) * 8)
        os.close(file)
        self._counts = np.frombuffer(self._map, dtype=np.int64, count=16)
        self._rows = np.frombuffer(self._map, dtype=np.float64, offset=_HEADER_BYTES).reshape(
            capacity, width + 2
        )

    @classmethod
    def create(cls, width: int, capacity: int) -> FrameRing:
        file, name = tempfile.mkstemp(prefix="workcell-ring-", dir=ring_folder())
        os.ftruncate(file, _HEADER_BYTES + capacity * (width + 2) * 8)
        return cls(Path(name), width, capacity, file)

    @classmethod
    def attach(cls, path: str | os.PathLike[str], width: int, capacity: int) -> FrameRing:
        return cls(Path(path), width, capacity, os.open(path, os.O_RDWR))

    def unlink(self) -> None:
        """Remove the file (both ends keep their mapping)."""
        self.path.unlink(missing_ok=True)

    def close(self) -> None:
        del self._counts, self._rows
        self._map.close()

    @property
    def published(self) -> int:
        return int(self._counts[_PUBLISHED // 8])

    @property
    def consumed(self) -> int:
        return int(self._counts[_CONSUMED // 8])

    # --- the recording side ----------------------------------------------------------------

    def publish(
        self, trial_number: int, rows: NDArray[np.float64], *, alive: Callable[[], bool]
    ) -> None:
        """Copy ``rows`` into the ring (waiting while it is full, as long as ``alive()``)."""
        published = self.published
        for values in rows:
            while published - self.consumed >= self.capacity:
                if not alive():
                    raise BrokenPipeError("the writer process is gone")
                time.sleep(SPACE_WAIT_S)
            row = self._rows[published % self.capacity]
            row[0] = trial_number
            row[1:-1] = values
            row[-1] = zlib.crc32(row[:-1])
            published += 1
            self._counts[_PUBLISHED // 8] = published

    # --- the writer side -------------------------------------------------------------------

    def take(
        self, upto: int | None = None, *, trials_known: int
    ) -> list[tuple[int, NDArray[np.float64]]]:
        """Rows published and complete, up to position ``upto`` (all if None) and before
        the first row of a trial numbered ``trials_known`` or more (whose start has not
        arrived yet), as runs of (trial number, rows); the ring space is freed."""
        end = self.published if upto is None else upto
        start = self.consumed
        runs: list[tuple[int, list[NDArray[np.float64]]]] = []
        position = start
        while position < end:
            row = self._rows[position % self.capacity]
            if row[-1] != zlib.crc32(row[:-1]):
                break  # not completely visible yet
            number = int(row[0])
            if number >= trials_known:
                break
            if not runs or runs[-1][0] != number:
                runs.append((number, []))
            runs[-1][1].append(row[1:-1].copy())
            position += 1
        self._counts[_CONSUMED // 8] = position
        return [(number, np.array(rows)) for number, rows in runs]

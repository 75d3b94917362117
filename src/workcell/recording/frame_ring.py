"""A ring of captured frame rows in shared memory, from a recording process to its writer.

The recording process copies each batch of captured rows into the ring and moves a
counter; it makes no system call and builds no Python object per frame. The writer
process polls the ring, takes the rows in order and moves its own counter back. Each row
carries the number of the trial it belongs to and a checksum: the wrapping sum of the
row's 64-bit words plus the row's position in the ring. The writer takes a row only when
the checksum matches: once the row is completely visible, whatever the CPU's memory
ordering (a row seen half written sums to something else), and never a row left from an
earlier lap of the ring (its position differs). A sum, unlike a CRC, is one vectorised
pass over a whole batch: it costs the simulation a few microseconds a batch, not a few a
row. Rows are copied in blocks (at most two per batch, at the ring's end).

Layout of the mapped file: the published count (int64) at byte 0, the consumed count
(int64) at byte 64 (another cache line), then ``capacity`` rows of ``width + 2`` 64-bit
words: the trial number (float64), the ``width`` float64 values of a
:class:`~workcell.recording.frame_capture.FrameLayout` row, and the checksum (uint64).
"""

from __future__ import annotations

import mmap
import os
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

_HEADER_BYTES = 128
_PUBLISHED, _CONSUMED = 0, 8  # int64 slots of the header: bytes 0 and 64, two cache lines
_POPULATE = getattr(mmap, "MAP_POPULATE", 0)  # Linux
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
        # Mapped with its page tables filled in at once: a page fault per 4 KiB page on
        # the first lap would cost the simulation more than the copies themselves.
        self._map = mmap.mmap(
            file,
            _HEADER_BYTES + capacity * (width + 2) * 8,
            flags=mmap.MAP_SHARED | _POPULATE,
        )
        os.close(file)
        # The counts as Python ints without a NumPy scalar on the way (aligned 8-byte
        # loads and stores: never seen half written).
        self._counts = memoryview(self._map)[:_HEADER_BYTES].cast("q")
        self._rows = np.frombuffer(self._map, dtype=np.float64, offset=_HEADER_BYTES).reshape(
            capacity, width + 2
        )
        self._words = self._rows.view(np.uint64)
        self._positions = np.arange(capacity, dtype=np.uint64)

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
        self._counts.release()
        del self._rows, self._words
        self._map.close()

    @property
    def published(self) -> int:
        return int(self._counts[_PUBLISHED])

    @property
    def consumed(self) -> int:
        return int(self._counts[_CONSUMED])

    # --- the recording side ----------------------------------------------------------------

    def publish(
        self,
        trial_number: int,
        rows: NDArray[np.float64],
        *,
        alive: Callable[[], bool],
        full: Callable[[], None] | None = None,
    ) -> int:
        """Copy ``rows`` into the ring (waiting while it is full, as long as ``alive()``;
        ``full()`` is called once when it starts waiting), in as few block copies as the
        ring's end allows. Returns the rows now in the ring, not yet taken."""
        counts, capacity = self._counts, self.capacity
        published, n = counts[_PUBLISHED], len(rows)
        waited = False
        done = 0
        while done < n:  # once, as a rule: the ring has room and does not wrap
            free = capacity - (published - counts[_CONSUMED])
            if free <= 0:
                if not alive():
                    raise BrokenPipeError("the writer process is gone")
                if full is not None and not waited:
                    full()
                waited = True
                time.sleep(SPACE_WAIT_S)
                continue
            slot = published % capacity
            k = min(n - done, free, capacity - slot)
            self._write(slot, published, trial_number, rows[done : done + k])
            published += k
            done += k
            counts[_PUBLISHED] = published
        return published - counts[_CONSUMED]

    def _write(
        self, slot: int, position: int, trial_number: int, rows: NDArray[np.float64]
    ) -> None:
        """Rows into the ring at ``slot`` (ring position ``position``), checksums last."""
        k = len(rows)
        block = self._rows[slot : slot + k]
        block[:, 0] = trial_number
        block[:, 1:-1] = rows
        self._words[slot : slot + k, -1] = self._checksums(slot, position, k)

    # --- the writer side -------------------------------------------------------------------

    def take(
        self, upto: int | None = None, *, trials_known: int
    ) -> list[tuple[int, NDArray[np.float64]]]:
        """Rows published and complete, up to position ``upto`` (all if None) and before
        the first row of a trial numbered ``trials_known`` or more (whose start has not
        arrived yet), as runs of (trial number, rows); the ring space is freed."""
        end = self.published if upto is None else upto
        position = self.consumed
        runs: list[tuple[int, NDArray[np.float64]]] = []
        while position < end:
            slot = position % self.capacity
            k = min(end - position, self.capacity - slot)
            block = self._rows[slot : slot + k]
            complete = self._words[slot : slot + k, -1] == self._checksums(slot, position, k)
            numbers = block[:, 0]
            usable = complete & (numbers < trials_known)
            whole = bool(usable.all())
            k = k if whole else int(np.argmin(usable))  # up to the first unusable
            if k == 0:
                break
            starts = np.flatnonzero(np.diff(numbers[:k])) + 1
            for first, last in zip((0, *starts), (*starts, k), strict=True):
                number = int(numbers[first])
                chunk = block[first:last, 1:-1].copy()
                if runs and runs[-1][0] == number:  # a trial's run across the ring's end
                    runs[-1] = (number, np.concatenate((runs[-1][1], chunk)))
                else:
                    runs.append((number, chunk))
            position += k
            if not whole:
                break
        self._counts[_CONSUMED] = position
        return runs

    def _checksums(self, slot: int, position: int, k: int) -> NDArray[np.uint64]:
        """The checksums of rows ``slot`` .. ``slot + k`` (trial number and values) as
        published at ring position ``position``: each row's words summed (wrapping), plus
        its position, so that a row left from an earlier lap never passes for the one
        published at its place."""
        sums: NDArray[np.uint64] = self._words[slot : slot + k, :-1].sum(axis=1, dtype=np.uint64)
        sums += self._positions[:k]
        sums += np.uint64(position)
        return sums

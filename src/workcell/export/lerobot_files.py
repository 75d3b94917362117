"""The growing data and video files of a LeRobot export, rolled over at size limits."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pyarrow.parquet as pq  # type: ignore[import-untyped, unused-ignore]

from workcell.export.lerobot_layout import (
    DATA_FILES_SIZE_IN_MB,
    DATA_PATH,
    VIDEO_FILES_SIZE_IN_MB,
    VIDEO_PATH,
    FileCursor,
)
from workcell.render.video_concat import VideoConcatenation

MB = 1024 * 1024


class DataFiles:
    """``data/chunk-*/file-*.parquet``: episodes appended, a new file past the limit."""

    def __init__(self, root: Path, limit_mb: float = DATA_FILES_SIZE_IN_MB) -> None:
        self.root = root
        self.limit = limit_mb * MB
        self.cursor = FileCursor()
        self._writer: Any = None
        self._bytes = 0

    def write(self, table: Any) -> tuple[int, int]:
        """Append one episode's rows; returns the (chunk, file) index they went to."""
        if self._writer is not None and self._bytes + table.nbytes > self.limit:
            self._close_file()
            self.cursor.advance()
        if self._writer is None:
            path = self.root / self.cursor.format(DATA_PATH)
            path.parent.mkdir(parents=True, exist_ok=True)
            self._writer = pq.ParquetWriter(path, table.schema, compression="snappy")
        self._writer.write_table(table)
        self._bytes += table.nbytes
        return self.cursor.chunk_index, self.cursor.file_index

    def _close_file(self) -> None:
        if self._writer is not None:
            self._writer.close()
            self._writer = None
            self._bytes = 0

    def close(self) -> None:
        self._close_file()


class VideoFiles:
    """``videos/<key>/chunk-*/file-*.mp4`` of one camera: each episode's video appended
    whole, without re-encoding (see :class:`VideoConcatenation`), a new file past the
    limit."""

    def __init__(
        self,
        root: Path,
        key: str,
        fps: int,
        limit_mb: float = VIDEO_FILES_SIZE_IN_MB,
    ) -> None:
        self.root = root
        self.key = key
        self.fps = fps
        self.limit = limit_mb * MB
        self.cursor = FileCursor()
        self._file: VideoConcatenation | None = None

    def begin_episode(self) -> tuple[int, int, float]:
        """Where the next episode starts: (chunk, file, from_timestamp in that file)."""
        if self._file is not None and _size(self._file.path) >= self.limit:
            self._file.close()
            self._file = None
            self.cursor.advance()
        if self._file is None:
            path = self.root / self.cursor.format(VIDEO_PATH, video_key=self.key)
            self._file = VideoConcatenation(path, self.fps)
        return (
            self.cursor.chunk_index,
            self.cursor.file_index,
            self._file.frame_count / self.fps,
        )

    def append(self, video: Path, frames: int) -> None:
        """Append the episode's video file (``frames`` frames, the encoding of the rest)."""
        assert self._file is not None, "begin_episode() first"
        self._file.append(video, frames)

    def close(self) -> None:
        if self._file is not None:
            self._file.close()
            self._file = None


def _size(path: Path) -> int:
    """Bytes written so far (the muxer creates the file with its first frame)."""
    return path.stat().st_size if path.exists() else 0

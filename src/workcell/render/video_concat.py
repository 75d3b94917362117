"""MP4 files joined without re-encoding, and what decides whether two files can be joined.

:class:`VideoConcatenation` writes one MP4 file whose video is whole H.264 files (segments)
one after another, their packets copied (remuxed) with their timestamps shifted: the
frames are bit for bit those of the segments, at ``i / fps`` seconds for the file's frame
``i``. Segments can share a file only when they share an encoding (:class:`VideoEncoding`:
codec, size, pixel format, frame rate and the codec's parameter sets); :func:`probe` reads
a file's encoding, frame count and keyframe spacing, :func:`writer_encoding` the encoding
that :class:`workcell.render.VideoWriter` produces.
"""

from __future__ import annotations

import functools
import itertools
import tempfile
from dataclasses import dataclass
from fractions import Fraction
from pathlib import Path

import av
import numpy as np

from workcell.closing import Closing
from workcell.errors import RenderError
from workcell.render.video import KEYFRAME_INTERVAL, VideoWriter


@dataclass(frozen=True)
class VideoEncoding:
    """What two video streams must share to be joined into one stream."""

    codec: str
    width: int
    height: int
    pix_fmt: str | None
    fps: Fraction
    extradata: bytes
    """The codec's parameter sets (H.264: SPS and PPS), as the MP4 file stores them."""

    def differences(self, other: VideoEncoding) -> list[str]:
        """What differs from ``other``, in words (empty: the same encoding)."""
        found = []
        if (self.codec, self.pix_fmt) != (other.codec, other.pix_fmt):
            found.append(f"{self.codec} {self.pix_fmt}, not {other.codec} {other.pix_fmt}")
        if (self.width, self.height) != (other.width, other.height):
            found.append(f"{self.width}x{self.height}, not {other.width}x{other.height}")
        if self.fps != other.fps:
            found.append(f"{self.fps} frames/s, not {other.fps}")
        if not found and self.extradata != other.extradata:
            found.append("other encoder settings (H.264 parameter sets)")
        return found


@dataclass(frozen=True)
class VideoInfo:
    """One MP4 file's video stream."""

    encoding: VideoEncoding
    frames: int
    """Coded frames (packets with data) in the file."""
    longest_gop: int
    """The most frames from a keyframe to the next one (or to the end)."""


def probe(path: str | Path) -> VideoInfo:
    """The encoding, frame count and keyframe spacing of the video file at ``path`` (reads
    its packets, decodes nothing)."""
    try:
        with av.open(str(path)) as container:
            if not container.streams.video:
                raise RenderError(f"{path} holds no video stream")
            stream = container.streams.video[0]
            context = stream.codec_context
            rate = stream.average_rate or stream.guessed_rate
            encoding = VideoEncoding(
                codec=context.name,
                width=context.width,
                height=context.height,
                pix_fmt=context.pix_fmt,
                fps=Fraction(rate) if rate else Fraction(0),
                extradata=bytes(context.extradata or b""),
            )
            keyframes = [p.is_keyframe for p in container.demux(stream) if p.size]
    except (OSError, av.FFmpegError) as error:
        raise RenderError(f"cannot read video {path}: {error}") from error
    return VideoInfo(encoding, len(keyframes), _longest_gop(keyframes))


def _longest_gop(keyframes: list[bool]) -> int:
    starts = [i for i, key in enumerate(keyframes) if key] + [len(keyframes)]
    if not keyframes or starts[0] != 0:
        return len(keyframes)  # no keyframe first: nothing decodes on its own
    return max((b - a for a, b in itertools.pairwise(starts)), default=0)


@functools.cache
def writer_encoding(
    width: int, height: int, fps: int, keyframe_interval: int | None = KEYFRAME_INTERVAL
) -> VideoEncoding:
    """The encoding :class:`VideoWriter` gives a video of this size and rate (found by
    encoding one black frame; the same for any content)."""
    with tempfile.TemporaryDirectory(prefix="workcell-probe-") as folder:
        path = Path(folder) / "probe.mp4"
        with VideoWriter(path, width, height, fps, keyframe_interval=keyframe_interval) as w:
            w.write(np.zeros((height, width, 3), dtype=np.uint8))
        return probe(path).encoding


class VideoConcatenation(Closing):
    """An MP4 file of whole video files appended one after another, without re-encoding.

    Every appended file must have the encoding of the first (see :class:`VideoEncoding`).
    Use as a context manager, or call :meth:`close` to finalise the file.
    """

    def __init__(self, path: str | Path, fps: int) -> None:
        self.path = Path(path)
        self.fps = fps
        self.encoding: VideoEncoding | None = None
        self._frames = 0
        self._container: av.container.OutputContainer | None = None
        self._stream: av.video.stream.VideoStream | None = None

    @property
    def frame_count(self) -> int:
        """Frames appended so far."""
        return self._frames

    def append(self, segment: str | Path, frames: int | None = None) -> int:
        """Append every frame of the video file ``segment``; returns how many. ``frames``:
        the count it must have (checked before anything is written)."""
        info = probe(segment)
        problems = []
        if frames is not None and info.frames != frames:
            problems.append(f"it has {info.frames} frames, not {frames}")
        if info.encoding.fps != self.fps:
            problems.append(f"it runs at {info.encoding.fps} frames/s, not {self.fps}")
        if self.encoding is not None:
            problems += info.encoding.differences(self.encoding)
        if problems:
            raise RenderError(f"cannot append {segment} to {self.path}: {'; '.join(problems)}")
        with av.open(str(segment)) as source:
            stream = source.streams.video[0]
            if self._container is None:
                self._open(stream)
            assert self._stream is not None and self._container is not None
            time_base = stream.time_base
            assert time_base is not None
            offset = Fraction(self._frames, self.fps) / time_base
            if offset.denominator != 1:
                raise RenderError(
                    f"cannot append {segment}: its time base {time_base} does not count "
                    f"whole frames at {self.fps} frames/s"
                )
            for packet in source.demux(stream):
                if packet.dts is None:  # the demuxer's empty end-of-stream packet
                    continue
                packet.dts += int(offset)
                if packet.pts is not None:
                    packet.pts += int(offset)
                packet.stream = self._stream
                self._container.mux(packet)
        self._frames += info.frames
        if self.encoding is None:
            self.encoding = info.encoding
        return info.frames

    def _open(self, template: av.video.stream.VideoStream) -> None:
        self.path.parent.mkdir(parents=True, exist_ok=True)
        try:
            self._container = av.open(
                str(self.path), mode="w", format="mp4", options={"movflags": "+faststart"}
            )
        except (OSError, av.FFmpegError) as error:
            raise RenderError(f"cannot write video {self.path}: {error}") from error
        self._stream = self._container.add_stream_from_template(template)

    def close(self) -> None:
        """Finalise the file; closing twice is harmless."""
        if self._container is not None:
            container, self._container = self._container, None
            container.close()

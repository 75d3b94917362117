"""MP4 video output: H.264 (libx264, yuv420p) through PyAV, playable in browsers.

A keyframe every :data:`KEYFRAME_INTERVAL` frames: a reader that seeks to a random frame
(LeRobot's data loader does, once per sample) decodes from the keyframe at or before it,
so the interval bounds the frames decoded per access. libx264's own default (250 frames,
plus scene cuts) made a random frame cost several times more to decode; LeRobot encodes
with a keyframe every 2 frames for the same reason. ``bench/video.py`` measures the choice.
"""

from __future__ import annotations

from collections.abc import Generator
from fractions import Fraction
from pathlib import Path

import av
import numpy as np
from numpy.typing import NDArray

from workcell.closing import Closing
from workcell.errors import RenderError

MAX_FPS = 240
KEYFRAME_INTERVAL = 2
"""Frames from one keyframe to the next (the GOP size); see the module's docstring."""
PRESET = "veryfast"
"""libx264's speed preset. Measured on 128x128 head-camera frames of an expert trial
(crf 23, a keyframe every 2 frames): 0.53 ms per frame against 0.90 ms with the default
``medium``, files 3 % smaller, mean absolute error 4.20 against 4.08 levels (0-255)."""


def read_frames(path: str | Path) -> Generator[NDArray[np.uint8], None, None]:
    """Every frame of the video file at ``path``, in order, as (height, width, 3) uint8 RGB."""
    try:
        with av.open(str(path)) as container:
            for frame in container.decode(container.streams.video[0]):
                yield np.asarray(frame.to_ndarray(format="rgb24"), dtype=np.uint8)
    except (OSError, av.FFmpegError) as error:
        raise RenderError(f"cannot read video {path}: {error}") from error


class VideoWriter(Closing):
    """Writes uint8 RGB frames of one fixed size to an MP4 file at a constant rate.

    H.264 in yuv420p halves the chroma resolution, so width and height must be even.
    Frame ``i`` is shown at ``i / fps`` seconds. ``keyframe_interval``: frames from one
    keyframe to the next (None: libx264's default of 250). Use as a context manager, or
    call :meth:`close` to finalise the file; parent folders are created.
    """

    def __init__(
        self,
        path: str | Path,
        width: int,
        height: int,
        fps: int | Fraction = 20,
        *,
        crf: int = 23,
        keyframe_interval: int | None = KEYFRAME_INTERVAL,
    ) -> None:
        problems = []
        for name, value in (("width", width), ("height", height)):
            if not isinstance(value, int) or value < 2:
                problems.append(f"video {name} = {value!r}: must be an integer of at least 2")
            elif value % 2:
                problems.append(
                    f"video {name} = {value}: H.264 (yuv420p) needs an even size; "
                    f"render at {value - 1} or {value + 1}"
                )
        if not (isinstance(fps, int | Fraction) and 0 < fps <= MAX_FPS):
            problems.append(f"video fps = {fps!r}: must be an int or Fraction in (0, {MAX_FPS}]")
        if not (isinstance(crf, int) and 0 <= crf <= 51):
            problems.append(f"video crf = {crf!r}: must be an integer from 0 (lossless) to 51")
        if keyframe_interval is not None and not (
            type(keyframe_interval) is int and keyframe_interval >= 1
        ):
            problems.append(
                f"video keyframe_interval = {keyframe_interval!r}: must be a whole number of "
                "frames, at least 1 (or None for the encoder's default)"
            )
        if problems:
            raise RenderError("; ".join(problems))
        self.path = Path(path)
        self.width = width
        self.height = height
        self.fps = Fraction(fps)
        self._frames = 0
        self.path.parent.mkdir(parents=True, exist_ok=True)
        try:
            self._container: av.container.OutputContainer | None = av.open(
                str(self.path), mode="w", format="mp4", options={"movflags": "+faststart"}
            )
        except (OSError, av.FFmpegError) as error:
            raise RenderError(f"cannot write video {self.path}: {error}") from error
        self._stream = self._container.add_stream("libx264", rate=self.fps)
        self._stream.width = width
        self._stream.height = height
        self._stream.pix_fmt = "yuv420p"
        self._stream.time_base = 1 / self.fps
        options = {"crf": str(crf), "preset": PRESET}
        if keyframe_interval is not None:
            options["g"] = str(keyframe_interval)
        self._stream.codec_context.options = options
        self.keyframe_interval = keyframe_interval

    @property
    def frame_count(self) -> int:
        """Frames written so far."""
        return self._frames

    def write(self, frame: NDArray[np.uint8]) -> None:
        """Append one (height, width, 3) uint8 RGB frame."""
        if self._container is None:
            raise RenderError(f"video {self.path} is already closed; no more frames can be added")
        expected = (self.height, self.width, 3)
        if frame.dtype != np.uint8 or frame.shape != expected:
            raise RenderError(
                f"video frame of shape {frame.shape} and dtype {frame.dtype}: "
                f"this video needs {expected} uint8 RGB frames"
            )
        video_frame = av.VideoFrame.from_ndarray(np.ascontiguousarray(frame), format="rgb24")
        video_frame.pts = self._frames
        # The frame clock is 1/fps; the stream's own time base changes once the muxer has
        # written the header, so it must not be used here.
        video_frame.time_base = 1 / self.fps
        self._container.mux(self._stream.encode(video_frame))
        self._frames += 1

    def close(self) -> None:
        """Flush the encoder and finalise the file; closing twice is harmless."""
        if self._container is None:
            return
        container, self._container = self._container, None
        try:
            container.mux(self._stream.encode(None))
        finally:
            container.close()

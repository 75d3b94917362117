"""Where an export's camera images come from: the trial's recorded videos, or rendering.

``workcell collect --cameras`` records one MP4 per trial and camera
(:mod:`workcell.recording.media`) and names each file in the trial's ``media`` event with its
frame count and sha256. An export uses such a video, instead of rendering the camera from
the recorded states, when it is the camera and the size asked for, its file is still the
one recorded (sha256), it holds one frame per recorded frame at the session's frame rate
and, for exports that copy it into their own videos (LeRobot), it has the encoding of
their videos (:func:`workcell.render.video_concat.writer_encoding`: same encoder settings,
a keyframe every :data:`~workcell.render.video.KEYFRAME_INTERVAL` frames). Otherwise, or
when asked to (``--rerender``), the camera is rendered, and :attr:`CameraSource.reason`
says why.
"""

from __future__ import annotations

import hashlib
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from workcell.errors import ConfigError, RenderError
from workcell.export.options import ExportOptions, ImageSize
from workcell.record.entries import EventRecord
from workcell.record.media_paths import recorded_file_path
from workcell.render.video import KEYFRAME_INTERVAL
from workcell.render.video_concat import VideoEncoding, probe

MEDIA_EVENT = "media"


@dataclass(frozen=True)
class RecordedVideo:
    """One camera's video as the trial's ``media`` event names it."""

    camera: str
    file: str
    """As recorded: relative to the store's folder."""
    path: Path
    frames: int
    sha256: str
    size: ImageSize


@dataclass(frozen=True)
class CameraSource:
    """Where one camera's images of one episode come from."""

    camera: str
    video: RecordedVideo | None
    """The recorded video used; None: rendered from the recorded states."""
    reason: str
    """Why it is rendered (empty when the recorded video is used)."""

    @property
    def recorded(self) -> bool:
        return self.video is not None

    def describe(self) -> str:
        """``head_cam: recorded video`` or ``head_cam: rendered (why)``."""
        return f"{self.camera}: " + (
            "recorded video" if self.video else f"rendered ({self.reason})"
        )

    def as_dict(self) -> dict[str, Any]:
        """For the provenance document."""
        return {
            "camera": self.camera,
            "source": "recorded" if self.video else "rendered",
            "file": self.video.file if self.video else None,
            "sha256": self.video.sha256 if self.video else None,
            "reason": self.reason or None,
        }


def recorded_videos(store_path: Path, events: Sequence[EventRecord]) -> dict[str, RecordedVideo]:
    """The trial's recorded camera videos, by camera (none without a ``media`` event)."""
    videos: dict[str, RecordedVideo] = {}
    for event in events:
        if event.kind != MEDIA_EVENT:
            continue
        payload = event.payload
        try:
            size = ImageSize(int(payload["width"]), int(payload["height"]))
            for entry in payload["files"]:
                camera, file = str(entry["camera"]), str(entry["file"])
                videos[camera] = RecordedVideo(
                    camera=camera,
                    file=file,
                    path=recorded_file_path(store_path, file),
                    frames=int(entry["frames"]),
                    sha256=str(entry["sha256"]),
                    size=size,
                )
        except (KeyError, TypeError, ValueError, ConfigError):
            continue  # not a media event this version wrote: its videos are not used
    return videos


def recorded_size(
    videos: Sequence[Mapping[str, RecordedVideo]], cameras: Sequence[str]
) -> ImageSize | None:
    """The size of the trials' recorded videos of ``cameras``, when there are some and
    they share one size (None otherwise)."""
    sizes = {trial[camera].size for trial in videos for camera in cameras if camera in trial}
    return sizes.pop() if len(sizes) == 1 else None


def camera_sources(
    videos: Mapping[str, RecordedVideo],
    n_frames: int,
    fps: int,
    options: ExportOptions,
    encoding: VideoEncoding | None,
) -> dict[str, CameraSource]:
    """Each camera of ``options`` with its source, for a trial of ``n_frames`` frames.
    ``encoding``: the encoding a recorded video must have to be used (None: any video
    that decodes)."""
    sources = {}
    for camera in options.cameras:
        video = videos.get(camera)
        if options.rerender:
            reason = "--rerender"
        elif video is None:
            reason = "not recorded with the trial"
        else:
            reason = _unusable(video, n_frames, fps, options.image_size, encoding)
        sources[camera] = CameraSource(camera, None if reason else video, reason)
    return sources


def _unusable(
    video: RecordedVideo, n_frames: int, fps: int, size: ImageSize, encoding: VideoEncoding | None
) -> str:
    """Why ``video`` cannot be used ("" when it can)."""
    if video.size != size:
        return f"recorded at {video.size}, the export is {size}"
    if video.frames != n_frames:
        return f"the media event counts {video.frames} frames, the trial {n_frames}"
    if not video.path.is_file():
        return f"{video.file} is missing"
    with video.path.open("rb") as file:
        digest = hashlib.file_digest(file, "sha256").hexdigest()
    if digest != video.sha256:
        return f"{video.file} is not the file recorded (its sha256 differs)"
    try:
        info = probe(video.path)
    except RenderError as error:
        return str(error)
    if info.frames != n_frames or info.encoding.fps != fps:
        return f"{video.file} holds {info.frames} frames at {info.encoding.fps} frames/s"
    if encoding is not None:
        differences = info.encoding.differences(encoding)
        if differences:
            return f"{video.file} is encoded differently: {'; '.join(differences)}"
        if info.longest_gop > KEYFRAME_INTERVAL:
            return (
                f"{video.file} has up to {info.longest_gop} frames between keyframes; the "
                f"export's videos have {KEYFRAME_INTERVAL}"
            )
    return ""

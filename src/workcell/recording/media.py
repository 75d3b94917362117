"""Camera videos recorded with the frames: one MP4 per trial and camera, frame for frame.

The robot's cameras (``head_cam``, ``wrist_l_cam``, ``wrist_r_cam``) are rendered offscreen
(shadows off, ``fast`` quality unless asked: :mod:`workcell.render.quality`) at every
recorded frame, so video frame i is frame i of the trial. Files live
in a media folder beside the store (``<store>.media/<trial_id>/<camera>.mp4``); the trial's
``media`` event names each file with its frame count and sha256. They are encoded as the
exports encode their videos (:class:`workcell.render.VideoWriter`'s defaults: a keyframe
every 2 frames), so an export copies them as they are (:mod:`workcell.export.camera_sources`).
Each frame's state is copied and drawn in a thread beside the simulation
(:mod:`workcell.recording.render_thread`), then encoded in another
(:mod:`workcell.recording.encoder_thread`); :meth:`MediaRecorder.end` waits for both.
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass
from fractions import Fraction
from pathlib import Path
from typing import Any, cast

import mujoco

from workcell.errors import ConfigError
from workcell.recording.render_thread import RenderThread
from workcell.render import (
    CAMERA_QUALITY,
    RENDER_QUALITIES,
    OffscreenRenderer,
    RenderQuality,
    VideoWriter,
)

CAMERAS: tuple[str, ...] = ("head_cam", "wrist_l_cam", "wrist_r_cam")


@dataclass(frozen=True)
class CameraOptions:
    cameras: tuple[str, ...]
    width: int = 128
    height: int = 128
    quality: RenderQuality = CAMERA_QUALITY

    def __post_init__(self) -> None:
        problems = [
            f"--cameras: unknown camera {c!r}; choose from {', '.join(CAMERAS)}"
            for c in self.cameras
            if c not in CAMERAS
        ]
        if not self.cameras:
            problems.append("--cameras: name at least one camera")
        for name, value in (("width", self.width), ("height", self.height)):
            if not (16 <= value <= 1920 and value % 2 == 0):
                problems.append(f"--camera-size {name} = {value}: must be even, 16 to 1920")
        if self.quality not in RENDER_QUALITIES:
            allowed = ", ".join(RENDER_QUALITIES)
            problems.append(f"--camera-quality = {self.quality!r}: must be one of {allowed}")
        if problems:
            raise ConfigError(problems)

    @staticmethod
    def parse(cameras: str, size: str, quality: str = CAMERA_QUALITY) -> CameraOptions:
        try:
            width, height = (int(v) for v in size.lower().split("x"))
        except ValueError:
            raise ConfigError([f"--camera-size = {size!r}: must be WIDTHxHEIGHT"]) from None
        names = tuple(c.strip() for c in cameras.split(",") if c.strip())
        return CameraOptions(names, width, height, cast(RenderQuality, quality))


class MediaRecorder:
    """Renders the cameras at each frame into the current trial's videos."""

    def __init__(
        self, model: mujoco.MjModel, options: CameraOptions, media_dir: Path, fps: float
    ) -> None:
        self.options = options
        self.fps = Fraction(fps).limit_denominator(1000)
        self.media_dir = media_dir
        self._renderer = RenderThread(
            model,
            lambda: OffscreenRenderer(
                model, options.width, options.height, shadows=False, quality=options.quality
            ),
        )
        self._writers: dict[str, VideoWriter] = {}
        self._folder: Path | None = None

    def start(self, trial_id: str) -> None:
        self._folder = self.media_dir / trial_id
        self._writers = {
            camera: VideoWriter(
                self._folder / f"{camera}.mp4", self.options.width, self.options.height, self.fps
            )
            for camera in self.options.cameras
        }

    def frame(self, data: mujoco.MjData) -> None:
        """Every camera as ``data`` is now: drawn and encoded beside the simulation."""
        self._renderer.put(data, tuple(self._writers.items()))

    def end(self) -> dict[str, Any]:
        """Close the trial's videos (once every frame is encoded); the payload of its
        ``media`` event."""
        self._renderer.drain()
        files = []
        for camera, writer in self._writers.items():
            writer.close()
            path = writer.path
            digest = hashlib.sha256(path.read_bytes()).hexdigest()
            files.append(
                {
                    "camera": camera,
                    "file": str(path.relative_to(self.media_dir.parent)),
                    "frames": writer.frame_count,
                    "sha256": digest,
                }
            )
        self._writers = {}
        options = self.options
        return {
            "files": files,
            "width": options.width,
            "height": options.height,
            "quality": options.quality,
        }

    def close(self) -> None:
        self._renderer.close()
        for writer in self._writers.values():
            writer.close()

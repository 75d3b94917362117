"""An export's camera images: which come from recorded videos, which are rendered.

:class:`CameraPlan` decides, once per export, the image size (the recorded one unless
asked otherwise) and, per episode and camera, the source (see :mod:`.camera_sources`);
it keeps what it decided for the progress lines, the summary and the provenance.
:func:`episode_images` gives an episode's images frame by frame from those sources.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Iterator, Mapping
from itertools import repeat
from typing import Any

import numpy as np
from numpy.typing import NDArray

from workcell.errors import RenderError
from workcell.export.camera_sources import (
    CameraSource,
    RecordedVideo,
    camera_sources,
    recorded_size,
    recorded_videos,
)
from workcell.export.loading import LoadedEpisode
from workcell.export.options import DEFAULT_SIZE, ExportOptions
from workcell.export.source import ExportSource
from workcell.record.store import Store
from workcell.render.video import read_frames
from workcell.render.video_concat import writer_encoding


class CameraPlan:
    """The camera sources of an export's episodes.

    ``copies_videos``: the export copies recorded videos into its own (LeRobot), so they
    must have its videos' encoding; otherwise (HDF5) they are decoded and any will do.
    """

    def __init__(
        self, store: Store, source: ExportSource, options: ExportOptions, copies_videos: bool
    ) -> None:
        self.fps = source.fps
        self.videos: dict[str, dict[str, RecordedVideo]] = {}
        if options.cameras:
            self.videos = {
                e.trial.trial_id: recorded_videos(source.path, store.events(e.trial.trial_id))
                for e in source.episodes
            }
        size = options.size or recorded_size(list(self.videos.values()), options.cameras)
        self.options = dataclasses.replace(options, size=size or DEFAULT_SIZE)
        size = self.options.image_size
        self.encoding = (
            writer_encoding(size.width, size.height, source.fps)
            if copies_videos and options.cameras
            else None
        )
        self.decided: list[dict[str, Any]] = []
        """Every decision so far, for the provenance document."""

    def sources(self, episode: LoadedEpisode) -> dict[str, CameraSource]:
        """Each camera's source for ``episode`` (recorded as decided)."""
        trial = episode.source.trial
        sources = camera_sources(
            self.videos.get(trial.trial_id, {}),
            episode.arrays.length,
            self.fps,
            self.options,
            self.encoding,
        )
        for chosen in sources.values():
            self.decided.append(
                {"episode_index": episode.index, "trial_id": trial.trial_id, **chosen.as_dict()}
            )
        return sources

    @property
    def recorded(self) -> int:
        """Camera streams taken from recorded videos so far."""
        return sum(d["source"] == "recorded" for d in self.decided)

    @property
    def rendered(self) -> int:
        """Camera streams rendered so far."""
        return sum(d["source"] == "rendered" for d in self.decided)


def describe(episode: LoadedEpisode, sources: Mapping[str, CameraSource], total: int) -> str:
    """The progress line of an episode's cameras."""
    parts = "; ".join(source.describe() for source in sources.values())
    return f"episode {episode.index + 1}/{total}: cameras {parts}"


def episode_images(
    episode: LoadedEpisode, sources: Mapping[str, CameraSource]
) -> Iterator[dict[str, NDArray[np.uint8]]]:
    """Per frame of ``episode``, one (height, width, 3) RGB image per camera of
    ``sources``: decoded from its recorded video, or rendered from the recorded states."""
    rendered = [camera for camera, source in sources.items() if source.video is None]
    decoded = {
        camera: read_frames(source.video.path)
        for camera, source in sources.items()
        if source.video is not None
    }
    renders: Iterator[dict[str, NDArray[np.uint8]]] = repeat({})
    if rendered:
        assert episode.world is not None, "rendering needs the episode's world"
        renders = episode.world.images(episode.states, rendered)
    try:
        for i, frame in zip(range(episode.arrays.length), renders, strict=False):
            images = dict(frame)
            for camera, frames in decoded.items():
                image = next(frames, None)
                if image is None:
                    video = sources[camera].video
                    raise RenderError(f"{video.file if video else camera} ends at frame {i}")
                images[camera] = image
            yield {camera: images[camera] for camera in sources}
    finally:
        for frames in decoded.values():
            frames.close()

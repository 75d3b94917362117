"""``export_lerobot``: a store's trials as a LeRobotDataset v3.0 (see :mod:`.lerobot_layout`).

Rows and conventions are those of :mod:`workcell.export.episode_data`. Camera videos, when
asked for, are each trial's recorded video where it can be used (copied without
re-encoding), else rendered from the recorded states after the replay check (see
:mod:`.camera_sources`); every episode's video is appended whole to its camera's file
(:class:`workcell.render.video_concat.VideoConcatenation`). ``info.json`` is written last,
so an export that failed half-way is not mistaken for a dataset.
"""

from __future__ import annotations

import json
import os
import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np
import pyarrow.parquet as pq  # type: ignore[import-untyped, unused-ignore]
from numpy.typing import NDArray

from workcell.export import stats as statistics
from workcell.export.boxes import environment_names
from workcell.export.camera_images import CameraPlan, describe, episode_images
from workcell.export.features import ACTION_KEY, ENVIRONMENT_KEY, STATE_KEY, image_key
from workcell.export.lerobot_files import DataFiles, VideoFiles
from workcell.export.lerobot_layout import (
    DONE_KEY,
    EPISODES_PATH,
    INFO_PATH,
    INTERVENTION_KEY,
    PROVENANCE_JSON_PATH,
    PROVENANCE_TABLE_PATH,
    REWARD_KEY,
    STATS_PATH,
    SUCCESS_KEY,
    TASKS_PATH,
    FileCursor,
    dataset_features,
    info_json,
)
from workcell.export.lerobot_tables import (
    data_table,
    episodes_table,
    provenance_table,
    tasks_table,
)
from workcell.export.loading import ExportSummary, LoadedEpisode, Progress, load_episodes
from workcell.export.manifest import provenance_document
from workcell.export.options import ExportOptions
from workcell.export.provenance import Provenance
from workcell.export.replay_world import WorldPool
from workcell.export.source import ExportSource, check_output, open_source
from workcell.record.store import Store
from workcell.render.video import VideoWriter

IMAGE_STATS_FRAMES = 100
"""Image statistics sample at most this many frames of each episode."""


def export_lerobot(
    store_path: str | os.PathLike[str],
    out_dir: str | os.PathLike[str],
    options: ExportOptions | None = None,
    progress: Progress | None = None,
) -> ExportSummary:
    """Export the store's selected trials into ``out_dir`` (new or empty)."""
    started = time.perf_counter()
    options = options or ExportOptions()
    out = check_output(out_dir)
    source = open_source(store_path, options.trials)
    out.mkdir(parents=True, exist_ok=True)
    with Store.open(source.path, writer=False) as store:
        cameras = CameraPlan(store, source, options, copies_videos=True)
        writer = _LeRobotWriter(out, source, cameras, progress)
        worlds = WorldPool(cameras.options.image_size) if options.cameras else None
        try:
            for episode in load_episodes(store, source, worlds, progress):
                writer.add(episode)
            writer.finish()
        finally:
            writer.close()
            if worlds is not None:
                worlds.close()
    return ExportSummary(
        out,
        len(source.episodes),
        writer.frames,
        len(options.cameras),
        time.perf_counter() - started,
        recorded_videos=cameras.recorded,
        rendered_videos=cameras.rendered,
        selection=source.selection,
    )


class _LeRobotWriter:
    def __init__(
        self, out: Path, source: ExportSource, cameras: CameraPlan, progress: Progress | None
    ) -> None:
        self.out = out
        self.source = source
        self.cameras = cameras
        self.options = options = cameras.options
        self.progress = progress
        self.fps = source.fps
        self.features = dataset_features(
            environment_names(source.pool_size, source.goal_names),
            options.cameras,
            options.image_size,
            source.fps,
        )
        self.data = DataFiles(out)
        self.videos = {
            camera: VideoFiles(out, image_key(camera), source.fps) for camera in options.cameras
        }
        self.tasks: dict[str, int] = {}
        self.rows: list[dict[str, Any]] = []
        self.stats: list[dict[str, statistics.Stats]] = []
        self.records: list[Provenance] = []
        self.frames = 0

    def add(self, episode: LoadedEpisode) -> None:
        arrays, record = episode.arrays, episode.provenance
        task_index = self.tasks.setdefault(record.task, len(self.tasks))
        n = arrays.length
        chunk, file = self.data.write(
            data_table(arrays, episode.index, self.frames, task_index, self.fps)
        )
        row: dict[str, Any] = {
            "episode_index": episode.index,
            "tasks": [record.task],
            "length": n,
            "data/chunk_index": chunk,
            "data/file_index": file,
            "dataset_from_index": self.frames,
            "dataset_to_index": self.frames + n,
        }
        episode_stats = self._vector_stats(episode, task_index)
        if self.videos:
            row.update(self._write_videos(episode, episode_stats))
        cursor = FileCursor()
        row["meta/episodes/chunk_index"] = cursor.chunk_index
        row["meta/episodes/file_index"] = cursor.file_index
        for feature, values in episode_stats.items():
            for name, value in values.items():
                row[f"stats/{feature}/{name}"] = value.tolist()
        self.rows.append(row)
        self.stats.append(episode_stats)
        self.records.append(record)
        self.frames += n

    def _vector_stats(self, episode: LoadedEpisode, task_index: int) -> dict[str, statistics.Stats]:
        arrays = episode.arrays
        n = arrays.length
        columns: dict[str, NDArray[Any]] = {
            STATE_KEY: arrays.state,
            ENVIRONMENT_KEY: arrays.environment,
            ACTION_KEY: arrays.action,
            REWARD_KEY: arrays.reward,
            DONE_KEY: arrays.done,
            SUCCESS_KEY: arrays.success,
            INTERVENTION_KEY: arrays.intervention,
            "timestamp": arrays.timestamps(self.fps),
            "frame_index": np.arange(n),
            "episode_index": np.full(n, episode.index),
            "index": np.arange(self.frames, self.frames + n),
            "task_index": np.full(n, task_index),
        }
        return {key: statistics.vector_stats(values) for key, values in columns.items()}

    def _write_videos(
        self, episode: LoadedEpisode, episode_stats: dict[str, statistics.Stats]
    ) -> dict[str, Any]:
        n = episode.arrays.length
        sources = self.cameras.sources(episode)
        if self.progress is not None:
            self.progress(describe(episode, sources, len(self.source.episodes)))
        columns: dict[str, Any] = {}
        for files in self.videos.values():
            chunk, file, start = files.begin_episode()
            key = files.key
            columns[f"videos/{key}/chunk_index"] = chunk
            columns[f"videos/{key}/file_index"] = file
            columns[f"videos/{key}/from_timestamp"] = start
            columns[f"videos/{key}/to_timestamp"] = start + n / self.fps
        every = max(1, -(-n // IMAGE_STATS_FRAMES))
        samples: dict[str, list[NDArray[np.uint8]]] = {camera: [] for camera in self.videos}
        with tempfile.TemporaryDirectory(prefix="workcell-export-") as folder:
            size = self.options.image_size
            segments = {
                camera: Path(folder) / f"{camera}.mp4"
                if source.video is None
                else source.video.path
                for camera, source in sources.items()
            }
            writers = {
                camera: VideoWriter(segments[camera], size.width, size.height, self.fps)
                for camera, source in sources.items()
                if source.video is None
            }
            try:
                for i, frame in enumerate(episode_images(episode, sources)):
                    for camera, image in frame.items():
                        if camera in writers:
                            writers[camera].write(image)
                        if i % every == 0:
                            samples[camera].append(image)
            finally:
                for writer in writers.values():
                    writer.close()
            for camera, files in self.videos.items():
                files.append(segments[camera], n)
        for camera, sampled in samples.items():
            episode_stats[image_key(camera)] = statistics.image_stats(sampled)
        return columns

    def finish(self) -> None:
        """Close the files and write the metadata (``info.json`` last)."""
        self.close()
        episodes_path = self.out / FileCursor().format(EPISODES_PATH)
        episodes_path.parent.mkdir(parents=True, exist_ok=True)
        pq.write_table(episodes_table(self.rows), episodes_path)
        pq.write_table(tasks_table(list(self.tasks)), self.out / TASKS_PATH)
        pq.write_table(provenance_table(self.records), self.out / PROVENANCE_TABLE_PATH)
        document = provenance_document(
            self.source, self.options, self.records, self.cameras.decided
        )
        _write_json(self.out / PROVENANCE_JSON_PATH, document)
        features = list(self.stats[0])
        dataset_stats = {
            key: statistics.to_json(statistics.aggregate([s[key] for s in self.stats]))
            for key in features
        }
        _write_json(self.out / STATS_PATH, dataset_stats)
        info = info_json(self.features, self.fps, len(self.rows), self.frames, len(self.tasks))
        _write_json(self.out / INFO_PATH, info)

    def close(self) -> None:
        self.data.close()
        for files in self.videos.values():
            files.close()


def _write_json(path: Path, value: Any) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(value, indent=4) + "\n")

"""The LeRobotDataset v3.0 layout: paths, file limits, feature descriptions, info.json.

::

    meta/info.json            codebase_version "v3.0", fps, features, path templates, totals
    meta/stats.json           per feature: min, max, mean, std, count, q01 .. q99
    meta/tasks.parquet        task text (the index) -> task_index
    meta/episodes/chunk-000/file-000.parquet    one row per episode: length, frame range,
                              data and video file and time range, per-episode stats
    data/chunk-000/file-000.parquet             frames of many episodes
    videos/<key>/chunk-000/file-000.mp4         frames of many episodes, one camera
    meta/workcell_provenance.parquet|json       Workcell's sidecar: each episode's trial

Files roll over to ``file-001`` and so on when they pass LeRobot's size limits (and to
``chunk-001`` after 1000 files), as LeRobot itself writes them.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from workcell.export.features import (
    ACTION_KEY,
    ACTION_NAMES,
    ENVIRONMENT_KEY,
    STATE_KEY,
    STATE_NAMES,
    image_key,
)
from workcell.export.options import ImageSize

CODEBASE_VERSION = "v3.0"
ROBOT_TYPE = "workcell_mobile_bimanual"
CHUNKS_SIZE = 1000
DATA_FILES_SIZE_IN_MB = 100
VIDEO_FILES_SIZE_IN_MB = 500
VIDEO_CODEC = "h264"

INFO_PATH = "meta/info.json"
STATS_PATH = "meta/stats.json"
TASKS_PATH = "meta/tasks.parquet"
CHUNK_FILE = "chunk-{chunk_index:03d}/file-{file_index:03d}"
EPISODES_PATH = "meta/episodes/" + CHUNK_FILE + ".parquet"
DATA_PATH = "data/" + CHUNK_FILE + ".parquet"
VIDEO_PATH = "videos/{video_key}/" + CHUNK_FILE + ".mp4"
PROVENANCE_TABLE_PATH = "meta/workcell_provenance.parquet"
PROVENANCE_JSON_PATH = "meta/workcell_provenance.json"

REWARD_KEY = "next.reward"
DONE_KEY = "next.done"
SUCCESS_KEY = "next.success"
INTERVENTION_KEY = "intervention"
"""Per frame: a person who took over from the trial's driver drove it (LeRobot's name, as
``lerobot-rollout --strategy.type=dagger`` records it)."""
INDEX_KEYS: tuple[str, ...] = ("timestamp", "frame_index", "episode_index", "index", "task_index")


@dataclass
class FileCursor:
    """Which chunk and file the next rows go to (mutable: it advances)."""

    chunk_index: int = 0
    file_index: int = 0

    def advance(self) -> None:
        """Move to the next file, and to the next chunk after :data:`CHUNKS_SIZE` files."""
        if self.file_index == CHUNKS_SIZE - 1:
            self.chunk_index += 1
            self.file_index = 0
        else:
            self.file_index += 1

    def format(self, template: str, **more: str) -> str:
        return template.format(chunk_index=self.chunk_index, file_index=self.file_index, **more)


def _vector(names: Sequence[str]) -> dict[str, Any]:
    return {"dtype": "float32", "shape": [len(names)], "names": list(names)}


def _scalar(dtype: str) -> dict[str, Any]:
    return {"dtype": dtype, "shape": [1], "names": None}


def video_feature(size: ImageSize, fps: int) -> dict[str, Any]:
    return {
        "dtype": "video",
        "shape": [size.height, size.width, 3],
        "names": ["height", "width", "channels"],
        "info": {
            "video.height": size.height,
            "video.width": size.width,
            "video.codec": VIDEO_CODEC,
            "video.pix_fmt": "yuv420p",
            "video.is_depth_map": False,
            "video.fps": fps,
            "video.channels": 3,
            "has_audio": False,
        },
    }


def dataset_features(
    environment: Sequence[str], cameras: Sequence[str], size: ImageSize, fps: int
) -> dict[str, dict[str, Any]]:
    """Every feature of the dataset with its dtype, shape and names, in column order
    (``environment``: the names of ``observation.environment_state``)."""
    features: dict[str, dict[str, Any]] = {
        STATE_KEY: _vector(STATE_NAMES),
        ENVIRONMENT_KEY: _vector(environment),
        ACTION_KEY: _vector(ACTION_NAMES),
    }
    for camera in cameras:
        features[image_key(camera)] = video_feature(size, fps)
    features[REWARD_KEY] = _scalar("float32")
    features[DONE_KEY] = _scalar("bool")
    features[SUCCESS_KEY] = _scalar("bool")
    features[INTERVENTION_KEY] = _scalar("bool")
    features["timestamp"] = _scalar("float32")
    for key in INDEX_KEYS[1:]:
        features[key] = _scalar("int64")
    return features


def info_json(
    features: dict[str, dict[str, Any]],
    fps: int,
    total_episodes: int,
    total_frames: int,
    total_tasks: int,
) -> dict[str, Any]:
    """The content of ``meta/info.json``."""
    has_video = any(ft["dtype"] == "video" for ft in features.values())
    return {
        "codebase_version": CODEBASE_VERSION,
        "robot_type": ROBOT_TYPE,
        "total_episodes": total_episodes,
        "total_frames": total_frames,
        "total_tasks": total_tasks,
        "chunks_size": CHUNKS_SIZE,
        "data_files_size_in_mb": DATA_FILES_SIZE_IN_MB,
        "video_files_size_in_mb": VIDEO_FILES_SIZE_IN_MB,
        "fps": fps,
        "splits": {"train": f"0:{total_episodes}"},
        "data_path": DATA_PATH,
        "video_path": VIDEO_PATH if has_video else None,
        "features": features,
    }

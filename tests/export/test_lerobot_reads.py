"""The LeRobot export read by the real ``lerobot`` (0.4.4, the learn extra) through its
documented API: ``LeRobotDatasetMetadata`` and ``LeRobotDataset(repo_id, root=...)``,
offline (the local root is read, nothing is downloaded), videos decoded with
``video_backend="pyav"`` (LeRobot's default, torchcodec, needs FFmpeg's shared libraries).
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np
import pyarrow.parquet as pq  # type: ignore[import-untyped, unused-ignore]
import pytest

from tests.learn_extra import require_learn_extra
from workcell.export.lerobot_layout import INFO_PATH, PROVENANCE_TABLE_PATH, VIDEO_PATH
from workcell.render.video import read_frames

REPO_ID = "workcell/tests"
"""Any name: with ``root`` given, LeRobot reads the folder and fetches nothing."""
BACKEND = "pyav"
STATE_SIZE, ACTION_SIZE = 39, 23
CHUNK = 10
"""Frames of action per sample in the delta_timestamps check."""

pytestmark = pytest.mark.filterwarnings(
    # LeRobot's pyav backend reads through torchvision.io.VideoReader, which warns that
    # torchvision's video decoding is deprecated (LeRobot's concern, not the export's).
    "ignore:The video decoding and encoding capabilities of torchvision:UserWarning"
)


def _dataset(root: Path, **options: Any) -> Any:
    from lerobot.datasets.lerobot_dataset import (  # type: ignore[import-untyped, import-not-found, unused-ignore]
        LeRobotDataset,
    )

    return LeRobotDataset(REPO_ID, root=root, video_backend=BACKEND, **options)


def _info(root: Path) -> dict[str, Any]:
    info: dict[str, Any] = json.loads((root / INFO_PATH).read_text())
    return info


@pytest.mark.parametrize("name", ["lerobot_dir", "lerobot_all_dir", "lerobot_video_dir"])
def test_metadata_is_what_info_json_says(name: str, request: pytest.FixtureRequest) -> None:
    require_learn_extra()
    from lerobot.datasets.lerobot_dataset import (  # type: ignore[import-untyped, import-not-found, unused-ignore]
        LeRobotDatasetMetadata,
    )

    root: Path = request.getfixturevalue(name)
    info = _info(root)
    meta = LeRobotDatasetMetadata(REPO_ID, root=root)
    assert meta.fps == info["fps"]
    assert (meta.total_episodes, meta.total_frames) == (
        info["total_episodes"],
        info["total_frames"],
    )
    assert list(meta.features) == list(info["features"])
    assert len(meta.episodes) == meta.total_episodes
    assert meta.stats is not None and "observation.state" in meta.stats
    sidecar = pq.read_table(root / PROVENANCE_TABLE_PATH).to_pydict()
    assert sidecar["episode_index"] == list(range(meta.total_episodes))


@pytest.mark.parametrize("name", ["lerobot_dir", "lerobot_video_dir", "lerobot_mixed_video_dir"])
def test_every_frame_loads_at_its_timestamp(name: str, request: pytest.FixtureRequest) -> None:
    """Every frame of every episode: index, timestamp (LeRobot checks each decoded video
    frame's time against it within 1e-4 s), task, shapes, next.done at the end."""
    require_learn_extra()
    import torch

    root: Path = request.getfixturevalue(name)
    dataset = _dataset(root)
    meta = dataset.meta
    assert len(dataset) == _info(root)["total_frames"]
    for episode in range(meta.total_episodes):
        row = meta.episodes[episode]
        start, stop = int(row["dataset_from_index"]), int(row["dataset_to_index"])
        items = [dataset[i] for i in range(start, stop)]
        assert [int(item["frame_index"]) for item in items] == list(range(stop - start))
        assert {int(item["episode_index"]) for item in items} == {episode}
        stamps = torch.stack([item["timestamp"] for item in items]).double()
        steps = stamps[1:] - stamps[:-1]
        assert torch.allclose(steps, torch.tensor(1 / meta.fps).double(), atol=1e-4, rtol=0)
        assert [bool(item["next.done"]) for item in items] == [False] * (len(items) - 1) + [True]
        first = items[0]
        assert tuple(first["observation.state"].shape) == (STATE_SIZE,)
        assert tuple(first["action"].shape) == (ACTION_SIZE,)
        assert isinstance(first["task"], str) and first["task"]
        for key in meta.video_keys:
            height, width, channels = meta.features[key]["shape"]
            assert tuple(first[key].shape) == (channels, height, width)
            assert 0.0 <= float(first[key].min()) <= float(first[key].max()) <= 1.0


def test_images_are_the_video_frames_of_their_row(lerobot_mixed_video_dir: Path) -> None:
    """LeRobot's image of a row is the exported video's frame of that row, both for the
    copied recordings (head_cam) and the rendered camera (wrist_r_cam)."""
    require_learn_extra()
    root = lerobot_mixed_video_dir
    dataset = _dataset(root)
    for key in dataset.meta.video_keys:
        video = root / VIDEO_PATH.format(video_key=key, chunk_index=0, file_index=0)
        frames = list(read_frames(video))
        assert len(frames) == len(dataset)
        for index in (0, 17, len(dataset) // 2, len(dataset) - 1):
            image = dataset[index][key].permute(1, 2, 0).numpy() * 255
            assert np.abs(image - frames[index]).max() <= 1.0, (key, index)


def test_delta_timestamps_give_padded_action_chunks(lerobot_video_dir: Path) -> None:
    require_learn_extra()
    fps = _info(lerobot_video_dir)["fps"]
    chunked = _dataset(
        lerobot_video_dir, delta_timestamps={"action": [i / fps for i in range(CHUNK)]}
    )
    end = int(chunked.meta.episodes[0]["dataset_to_index"])
    middle, last = chunked[end - CHUNK], chunked[end - 1]
    assert tuple(last["action"].shape) == (CHUNK, ACTION_SIZE)
    assert not bool(middle["action_is_pad"].any())
    assert bool(last["action_is_pad"][1:].all()) and not bool(last["action_is_pad"][0])
    assert np.array_equal(middle["action"][-1].numpy(), last["action"][0].numpy())


def test_a_data_loader_batches_it(lerobot_video_dir: Path) -> None:
    require_learn_extra()
    import torch

    dataset = _dataset(lerobot_video_dir)
    loader = torch.utils.data.DataLoader(dataset, batch_size=8, shuffle=True, num_workers=0)
    batch = next(iter(loader))
    assert tuple(batch["observation.state"].shape) == (8, STATE_SIZE)
    assert tuple(batch["observation.images.head_cam"].shape) == (8, 3, 48, 64)

"""Interop check: load a Workcell LeRobot export with the real ``lerobot`` package.

Not collected by pytest (no ``test_`` prefix): ``lerobot`` pulls torch (gigabytes), so it
stays out of the main environment. Run it in a venv of its own, against a fresh export::

    python3.11 -m venv /tmp/lerobot-venv
    /tmp/lerobot-venv/bin/pip install "lerobot==0.4.4"    # last release for Python 3.11
    export MUJOCO_GL=egl
    .venv/bin/workcell collect --mode collection --trials 2 --store /tmp/interop.sqlite
    .venv/bin/workcell collect --mode collection --trials 1 --store /tmp/interop.sqlite \\
        --set task.time_limit_s=3
    .venv/bin/workcell export --format lerobot --store /tmp/interop.sqlite \\
        --out /tmp/interop-dataset --cameras head_cam,wrist_l_cam --size 128x96
    /tmp/lerobot-venv/bin/python tests/interop/check_lerobot.py /tmp/interop-dataset \\
        --video-backend pyav     # torchcodec needs the system's FFmpeg shared libraries

It uses lerobot's documented API only (``LeRobotDatasetMetadata`` and
``LeRobotDataset(repo_id, root=...)``, offline: the local root is read, nothing is
downloaded) and checks that the metadata matches ``meta/info.json``; every frame loads with
its index, timestamp and task; camera frames decode at each frame's timestamp (lerobot
checks them against the video within its 1e-4 s tolerance); ``delta_timestamps`` give
action chunks padded at episode ends; a torch ``DataLoader`` batches it; and the Workcell
provenance sidecar has one row per episode. Prints one line per check; exit status 1 if
any fails.
"""

from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import Any

STATE_SIZE = 39
ACTION_SIZE = 23
CHUNK = 10
"""Frames of action per sample in the delta_timestamps check."""


class Checks:
    """Collects pass/fail lines."""

    def __init__(self) -> None:
        self.failed = 0

    def __call__(self, ok: bool, what: str) -> None:
        print(f"{'ok  ' if ok else 'FAIL'} {what}")
        self.failed += not ok


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0] if __doc__ else None)
    parser.add_argument("root", type=Path, help="a 'workcell export --format lerobot' folder")
    parser.add_argument("--repo-id", default="workcell/interop", help="any name; not fetched")
    parser.add_argument("--video-backend", default=None, help="pyav or torchcodec")
    args = parser.parse_args(argv)

    import pandas as pd  # type: ignore[import-not-found, import-untyped, unused-ignore]
    import torch  # type: ignore[import-not-found, unused-ignore]
    from lerobot.datasets.lerobot_dataset import (  # type: ignore[import-not-found, unused-ignore]
        LeRobotDataset,
        LeRobotDatasetMetadata,
    )

    check = Checks()
    root: Path = args.root
    info: dict[str, Any] = json.loads((root / "meta" / "info.json").read_text())

    meta = LeRobotDatasetMetadata(args.repo_id, root=root)
    check(meta.fps == info["fps"], f"metadata: fps {meta.fps}")
    check(meta.total_episodes == info["total_episodes"], f"episodes {meta.total_episodes}")
    check(meta.total_frames == info["total_frames"], f"frames {meta.total_frames}")
    check(list(meta.features) == list(info["features"]), "feature names and order")
    check(len(meta.episodes) == meta.total_episodes, "meta/episodes: one row per episode")
    check(meta.stats is not None and "observation.state" in meta.stats, "meta/stats.json")

    dataset = LeRobotDataset(args.repo_id, root=root, video_backend=args.video_backend)
    check(len(dataset) == info["total_frames"], f"dataset length {len(dataset)}")
    first = dataset[0]
    check(tuple(first["observation.state"].shape) == (STATE_SIZE,), "observation.state (39,)")
    check(tuple(first["action"].shape) == (ACTION_SIZE,), "action (23,)")
    check(isinstance(first["task"], str) and first["task"] != "", f"task {first['task']!r}")
    for key in meta.video_keys:
        height, width, channels = info["features"][key]["shape"]
        image = first[key]
        check(tuple(image.shape) == (channels, height, width), f"{key} {tuple(image.shape)}")
        check(0.0 <= float(image.min()) <= float(image.max()) <= 1.0, f"{key} in [0, 1]")

    fps = meta.fps
    for episode in range(meta.total_episodes):
        row = meta.episodes[episode]
        start, stop = int(row["dataset_from_index"]), int(row["dataset_to_index"])
        items = [dataset[i] for i in range(start, stop)]  # decodes every video frame
        stamps = torch.stack([item["timestamp"] for item in items]).double()
        frames = [int(item["frame_index"]) for item in items]
        # Timestamps are float32 in LeRobot; its own tolerance for them is 1e-4 s.
        period = torch.tensor(1 / fps).double()
        steady = bool(torch.allclose(stamps[1:] - stamps[:-1], period, rtol=0.0, atol=1e-4))
        check(frames == list(range(stop - start)) and steady, f"episode {episode}: timestamps")
        check(bool(items[-1]["next.done"]), f"episode {episode}: next.done on its last frame")

    chunked = LeRobotDataset(
        args.repo_id,
        root=root,
        video_backend=args.video_backend,
        delta_timestamps={"action": [i / fps for i in range(CHUNK)]},
    )
    last = chunked[int(meta.episodes[0]["dataset_to_index"]) - 1]
    check(tuple(last["action"].shape) == (CHUNK, ACTION_SIZE), "delta_timestamps: action chunk")
    check(bool(last["action_is_pad"][1:].all()), "delta_timestamps: padded past the end")

    loader = torch.utils.data.DataLoader(dataset, batch_size=8, shuffle=True, num_workers=0)
    batch = next(iter(loader))
    check(tuple(batch["observation.state"].shape) == (8, STATE_SIZE), "DataLoader batch")

    sidecar = pd.read_parquet(root / "meta" / "workcell_provenance.parquet")
    check(len(sidecar) == meta.total_episodes, "provenance sidecar: one row per episode")
    check(sidecar["episode_index"].tolist() == list(range(meta.total_episodes)), "in order")

    print("all checks passed" if not check.failed else f"{check.failed} checks failed")
    return 1 if check.failed else 0


if __name__ == "__main__":
    sys.exit(main())

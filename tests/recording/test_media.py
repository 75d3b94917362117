"""Cameras recorded during collection: one MP4 per trial and camera, frame for frame."""

from __future__ import annotations

import hashlib
from pathlib import Path

import av
import numpy as np
import pytest

from workcell.cli.main import main
from workcell.record import Store


def test_collect_records_camera_videos_frame_for_frame(tmp_path: Path) -> None:
    store = tmp_path / "cams.sqlite"
    args = ["collect", "--mode", "practice", "--store", str(store), "--json"]
    args += ["--cameras", "head_cam,wrist_r_cam", "--camera-size", "32x24"]
    assert main(args) == 0
    with Store.open(store, writer=False) as reader:
        (trial,) = reader.trials()
        (media,) = [e for e in reader.events(trial.trial_id) if e.kind == "media"]
    assert media.payload["quality"] == "fast"  # the default for per-frame cameras
    files = media.payload["files"]
    assert isinstance(files, list) and {f["camera"] for f in files} == {"head_cam", "wrist_r_cam"}
    for entry in files:
        path = tmp_path / entry["file"]
        assert hashlib.sha256(path.read_bytes()).hexdigest() == entry["sha256"]
        with av.open(str(path)) as container:
            frames = [f.to_ndarray(format="rgb24") for f in container.decode(video=0)]
        assert len(frames) == entry["frames"] == trial.n_frames
        assert frames[0].shape == (24, 32, 3)
        assert np.std(np.asarray(frames[-1], dtype=float)) > 5.0  # a picture, not a blank


def test_bad_camera_options_are_one_line_each(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    args = ["collect", "--store", str(tmp_path / "x.sqlite"), "--cameras", "tail_cam"]
    assert main([*args, "--camera-size", "33x10", "--camera-quality", "best"]) == 2
    errors = capsys.readouterr().err.strip().splitlines()
    assert len(errors) == 4
    assert "--camera-quality = 'best': must be one of fast, fine" in errors[3]
    assert "unknown camera 'tail_cam'" in errors[0]


def test_fine_camera_quality_is_recorded_as_asked(tmp_path: Path) -> None:
    store = tmp_path / "fine.sqlite"
    args = ["collect", "--mode", "collection", "--trials", "1", "--store", str(store)]
    args += ["--set", "task.time_limit_s=1", "--cameras", "head_cam", "--camera-size", "32x24"]
    assert main([*args, "--camera-quality", "fine"]) == 0
    with Store.open(store, writer=False) as reader:
        (trial,) = reader.trials()
        (media,) = [e for e in reader.events(trial.trial_id) if e.kind == "media"]
    assert media.payload["quality"] == "fine"

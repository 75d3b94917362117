"""Recorded stores and their exports, made once per test session and only read after."""

from __future__ import annotations

from pathlib import Path

import pytest

from tests.export import stores
from workcell.export.hdf5_export import export_hdf5
from workcell.export.lerobot_export import export_lerobot
from workcell.export.options import ExportOptions, ImageSize

CAMERAS = ("head_cam", "wrist_l_cam")
SIZE = ImageSize(64, 48)
RECORDED_CAMERAS = ("head_cam", "wrist_l_cam")
RECORDED_SIZE = ImageSize(64, 48)


@pytest.fixture(scope="session")
def recorded(tmp_path_factory: pytest.TempPathFactory) -> stores.Stores:
    return stores.build(tmp_path_factory.getbasetemp() / "recorded")


@pytest.fixture(scope="session")
def lerobot_dir(recorded: stores.Stores, tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The mixed store exported with the defaults: included trials, no cameras."""
    out = tmp_path_factory.mktemp("lerobot") / "dataset"
    export_lerobot(recorded.mixed, out)
    return out


@pytest.fixture(scope="session")
def lerobot_all_dir(recorded: stores.Stores, tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The mixed store exported with --all."""
    out = tmp_path_factory.mktemp("lerobot_all") / "dataset"
    export_lerobot(recorded.mixed, out, ExportOptions(include_all=True))
    return out


@pytest.fixture(scope="session")
def lerobot_video_dir(recorded: stores.Stores, tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The short store exported with two cameras at 64x48."""
    out = tmp_path_factory.mktemp("lerobot_video") / "dataset"
    export_lerobot(recorded.short, out, ExportOptions(cameras=CAMERAS, size=SIZE))
    return out


@pytest.fixture(scope="session")
def hdf5_path(recorded: stores.Stores, tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The mixed store exported to HDF5 with --all."""
    out = tmp_path_factory.mktemp("hdf5") / "dataset"
    return export_hdf5(recorded.mixed, out, ExportOptions(include_all=True)).out / "workcell.hdf5"


@pytest.fixture(scope="session")
def camera_store(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """Two 1.5 s trials recorded with head_cam and wrist_l_cam at 64x48 (their videos in
    ``cams.sqlite.media/``)."""
    store = tmp_path_factory.mktemp("cameras") / "cams.sqlite"
    cameras = ["--cameras", ",".join(RECORDED_CAMERAS), "--camera-size", str(RECORDED_SIZE)]
    stores.collect(
        store, "--trials", "2", "--seed", "6", "--set", "task.time_limit_s=1.5", *cameras
    )
    return store


@pytest.fixture(scope="session")
def lerobot_mixed_video_dir(camera_store: Path, tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The camera store exported with head_cam (its recorded videos, copied) and wrist_r_cam
    (not recorded: rendered), at the recorded 64x48."""
    out = tmp_path_factory.mktemp("lerobot_mixed") / "dataset"
    export_lerobot(camera_store, out, ExportOptions(cameras=("head_cam", "wrist_r_cam")))
    return out

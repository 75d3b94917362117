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

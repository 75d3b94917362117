"""Corrections in the exports (issue 35): the LeRobot dataset's per-frame boolean feature
``intervention`` (LeRobot's name), read by the real LeRobot, and the HDF5 export's
per-frame mask, both the store's ``intervention`` column frame by frame."""

from __future__ import annotations

import json
from pathlib import Path

import h5py  # type: ignore[import-untyped, unused-ignore]
import numpy as np
import pyarrow.parquet as pq  # type: ignore[import-untyped, unused-ignore]
import pytest

from tests.export.corrected import HAND_BACK_S, TAKE_OVER_S, record_corrected
from tests.learn_extra import require_learn_extra
from workcell.export.hdf5_export import export_hdf5
from workcell.export.lerobot_export import export_lerobot
from workcell.export.lerobot_layout import INFO_PATH, PROVENANCE_TABLE_PATH
from workcell.export.options import ExportOptions
from workcell.record.store import Store

pytestmark = pytest.mark.filterwarnings(
    "ignore:The video decoding and encoding capabilities of torchvision:UserWarning"
)


@pytest.fixture(scope="module")
def corrected(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, list[np.ndarray]]:
    """The store and each trial's recorded intervention flags, in trial order."""
    store = tmp_path_factory.mktemp("corrected") / "corrected.sqlite"
    record_corrected(store)
    with Store.open(store, writer=False) as reader:
        trials = reader.trials()
        flags = [np.asarray(reader.frames(t.trial_id)["intervention"]) for t in trials]
        assert [t.driver for t in trials] == ["expert", "expert"]
    for trial_flags in flags:
        corrected_rows = np.flatnonzero(trial_flags == 1.0)
        # the frames from the take-over to the hand-back, one stretch, at 20 Hz
        assert len(corrected_rows) == pytest.approx((HAND_BACK_S - TAKE_OVER_S) * 20, abs=1)
        assert corrected_rows[-1] - corrected_rows[0] + 1 == len(corrected_rows)
    return store, flags


def test_the_lerobot_dataset_marks_each_corrected_frame(
    corrected: tuple[Path, list[np.ndarray]], tmp_path: Path
) -> None:
    store, flags = corrected
    out = tmp_path / "dataset"
    export_lerobot(store, out, ExportOptions(include_all=True))
    info = json.loads((out / INFO_PATH).read_text())
    assert info["features"]["intervention"] == {"dtype": "bool", "shape": [1], "names": None}
    # who drove each episode, in the provenance sidecar beside meta/
    sidecar = pq.read_table(out / PROVENANCE_TABLE_PATH).to_pylist()
    assert [row["driver"] for row in sidecar] == ["expert"] * len(flags)
    require_learn_extra()
    from lerobot.datasets.lerobot_dataset import (  # type: ignore[import-untyped, import-not-found, unused-ignore]
        LeRobotDataset,
    )

    dataset = LeRobotDataset("workcell/tests", root=out, video_backend="pyav")
    read: list[list[bool]] = [[] for _ in flags]
    for i in range(len(dataset)):
        item = dataset[i]
        read[int(item["episode_index"])].append(bool(item["intervention"]))
    assert read == [[bool(v == 1.0) for v in trial] for trial in flags]


def test_the_hdf5_demos_carry_a_per_frame_mask(
    corrected: tuple[Path, list[np.ndarray]], tmp_path: Path
) -> None:
    store, flags = corrected
    path = (
        export_hdf5(store, tmp_path / "h5", ExportOptions(include_all=True)).out / "workcell.hdf5"
    )
    with h5py.File(path, "r") as file:
        masks = [file[f"data/demo_{i}/intervention"][:] for i in range(len(flags))]
        # who drove, with each demo's provenance
        assert [file[f"data/demo_{i}"].attrs["driver"] for i in range(len(flags))] == [
            "expert"
        ] * len(flags)
    for mask, trial in zip(masks, flags, strict=True):
        assert mask.dtype == np.int64
        assert mask.tolist() == (trial == 1.0).astype(int).tolist()

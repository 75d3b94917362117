"""Each new task's exports read by the libraries that use them, with their default
settings: one expert trial of palletize, sort and shelve recorded by ``workcell collect``,
exported by ``workcell export``, then loaded by the real LeRobot (``LeRobotDataset``,
offline), the real robomimic (``SequenceDataset``) and rerun's own reader. The episode's
language task is the trial's own instruction, the environment state holds the task's
objects and its goal, and the Rerun recording draws each box as the trial drew it (sort's
two kinds in their own sizes and colours)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import h5py  # type: ignore[import-untyped, unused-ignore]
import numpy as np
import pytest

from tests.learn_extra import require_learn_extra
from workcell.cli.main import main
from workcell.export.boxes import environment_names, goal_slice
from workcell.export.hdf5_export import HDF5_NAME
from workcell.record import Store
from workcell.tasks.registry import load_task

TASKS = ("palletize", "sort", "shelve")
REPO_ID = "workcell/tasks"
"""Any name: with ``root`` given, LeRobot reads the folder and fetches nothing."""

pytestmark = [
    pytest.mark.slow,
    pytest.mark.filterwarnings(
        "ignore:The video decoding and encoding capabilities of torchvision:UserWarning"
    ),
]


@pytest.fixture(scope="module", params=TASKS)
def exported(request: pytest.FixtureRequest, tmp_path_factory: pytest.TempPathFactory) -> Any:
    """(task, store, LeRobot folder, HDF5 file, Rerun folder) for one expert trial of the
    task."""
    task: str = request.param
    folder = tmp_path_factory.mktemp(task)
    store = folder / "s.sqlite"
    args = ["--store", str(store), "--task", task, "--mode", "collection", "--trials", "1"]
    assert main(["collect", *args, "--seed", "5"]) == 0
    lerobot, hdf5, rerun = folder / "lerobot", folder / "hdf5", folder / "rerun"
    for fmt, out in (("lerobot", lerobot), ("hdf5", hdf5), ("rerun", rerun)):
        assert main(["export", "--store", str(store), "--format", fmt, "--out", str(out)]) == 0
    return task, store, lerobot, hdf5 / HDF5_NAME, rerun


def _instruction(task: str, store: Path) -> tuple[str, int]:
    """The recorded trial's instruction and its frame count."""
    with Store.open(store, writer=False) as reader:
        (trial,) = reader.trials()
        (started,) = [e for e in reader.events(trial.trial_id) if e.kind == "trial_started"]
    assert trial.task == task and trial.outcome == "success"
    conditions = started.payload["conditions"]
    text = load_task(task).trial_instruction(int(trial.required_boxes), conditions)
    assert trial.n_frames is not None
    return text, trial.n_frames


def test_lerobot_loads_each_task_with_its_instruction(exported: Any) -> None:
    require_learn_extra()
    from lerobot.datasets.lerobot_dataset import (  # type: ignore[import-untyped, import-not-found, unused-ignore]
        LeRobotDataset,
    )

    task, store, root, _, _ = exported
    instruction, n_frames = _instruction(task, store)
    dataset = LeRobotDataset(REPO_ID, root=root, video_backend="pyav")
    assert dataset.meta.total_episodes == 1 and len(dataset) == n_frames
    names = dataset.meta.features["observation.environment_state"]["names"]
    goal = load_task(task).goal_names
    pool = len([n for n in names if n.endswith("_state") and n.startswith("box")])
    assert tuple(names) == environment_names(pool, goal)
    assert tuple(names[goal_slice(pool, goal)]) == goal
    for index in (0, n_frames - 1):
        item = dataset[index]
        assert item["task"] == instruction
        assert tuple(item["observation.environment_state"].shape) == (len(names),)
        assert int(item["frame_index"]) == index


def test_robomimic_loads_each_task(exported: Any) -> None:
    require_learn_extra()
    from robomimic.utils import obs_utils  # type: ignore[import-untyped, import-not-found, unused-ignore]
    from robomimic.utils.dataset import SequenceDataset  # type: ignore[import-untyped, import-not-found, unused-ignore]

    task, store, _, path, _ = exported
    _, n_frames = _instruction(task, store)
    keys = ("state", "environment_state")
    obs_utils.initialize_obs_modality_mapping_from_dict({"low_dim": list(keys)})
    dataset = SequenceDataset(str(path), keys, ("actions", "rewards", "dones"))
    assert len(dataset) == n_frames
    with h5py.File(path, "r") as file:
        environment = file["data/demo_0/obs/environment_state"][:]
        names = json.loads(file["data"].attrs["environment_state_names"])
        assert file["data"].attrs["total"] == n_frames
    last = dataset[n_frames - 1]
    np.testing.assert_array_equal(last["obs"]["environment_state"][0], environment[-1])
    goal = load_task(task).goal_names
    pool = len([n for n in names if n.endswith("_state") and n.startswith("box")])
    assert environment.shape[1] == len(names) and tuple(names) == environment_names(pool, goal)


def test_rerun_draws_each_box_as_the_trial_drew_it(exported: Any) -> None:
    import rerun as rr

    from workcell.export.rerun_export import recording_name
    from workcell.export.rerun_layout import BOXES_ENTITY, packed_rgba

    task, store, _, _, folder = exported
    with Store.open(store, writer=False) as reader:
        (trial,) = reader.trials()
        (started,) = [e for e in reader.events(trial.trial_id) if e.kind == "trial_started"]
    conditions = started.payload["conditions"]
    recording = rr.dataframe.load_recording(str(folder / recording_name(0, trial.trial_id)))
    boxes = "/" + BOXES_ENTITY.strip("/")
    static = recording.view(index="frame", contents=boxes).select_static().read_all()
    half_sizes = np.asarray(static.column(f"{boxes}:Boxes3D:half_sizes").to_pylist()[0])
    frames = recording.view(index="frame", contents=boxes).select().read_all()
    colours = frames.column(f"{boxes}:Boxes3D:colors").to_pylist()
    seen = {int(c) for row in colours for c in row}
    if task == "sort":  # each box in its kind's size, the active ones in its kind's colour
        layout = conditions["task"]
        kinds = [int(k) for k in layout["box_kinds"]]
        sizes = [layout[f"kind_{k}_size"] for k in kinds]
        np.testing.assert_allclose(half_sizes, np.asarray(sizes) / 2, atol=1e-6)
        assert len({tuple(h) for h in half_sizes.round(6)}) == 2
        for k in (0, 1):
            rgba = np.round(np.asarray(layout[f"kind_{k}_rgba"]) * 255)
            assert int(packed_rgba(rgba)) in seen
    else:  # every box the trial's one box
        size = np.asarray(conditions["box_size"])
        np.testing.assert_allclose(half_sizes, np.tile(size / 2, (len(half_sizes), 1)), atol=1e-6)
        rgba = np.round(np.asarray(conditions["box_rgba"]) * 255)
        assert int(packed_rgba(rgba)) in seen

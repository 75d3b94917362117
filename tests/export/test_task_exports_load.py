"""Each new task's exports read by the libraries that learn from them, with their default
settings: one expert trial of palletize, sort and shelve recorded by ``workcell collect``,
exported by ``workcell export``, then loaded by the real LeRobot (``LeRobotDataset``,
offline) and the real robomimic (``SequenceDataset``). The episode's language task is the
trial's own instruction, and the environment state is as wide as the task's observation
says (its objects and its goal)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import h5py  # type: ignore[import-untyped, unused-ignore]
import numpy as np
import pytest

from tests.learn_extra import require_learn_extra
from workcell.cli.main import main
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
    """(task, store, LeRobot folder, HDF5 file) for one expert trial of the task."""
    task: str = request.param
    folder = tmp_path_factory.mktemp(task)
    store = folder / "s.sqlite"
    args = ["--store", str(store), "--task", task, "--mode", "collection", "--trials", "1"]
    assert main(["collect", *args, "--seed", "5"]) == 0
    lerobot, hdf5 = folder / "lerobot", folder / "hdf5"
    for fmt, out in (("lerobot", lerobot), ("hdf5", hdf5)):
        assert main(["export", "--store", str(store), "--format", fmt, "--out", str(out)]) == 0
    return task, store, lerobot, hdf5 / HDF5_NAME


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

    task, store, root, _ = exported
    instruction, n_frames = _instruction(task, store)
    dataset = LeRobotDataset(REPO_ID, root=root, video_backend="pyav")
    assert dataset.meta.total_episodes == 1 and len(dataset) == n_frames
    names = dataset.meta.features["observation.environment_state"]["names"]
    goal = load_task(task).goal_names
    assert tuple(names[-len(goal) :]) == goal and (len(names) - len(goal)) % 8 == 0
    for index in (0, n_frames - 1):
        item = dataset[index]
        assert item["task"] == instruction
        assert tuple(item["observation.environment_state"].shape) == (len(names),)
        assert int(item["frame_index"]) == index


def test_robomimic_loads_each_task(exported: Any) -> None:
    require_learn_extra()
    from robomimic.utils import obs_utils  # type: ignore[import-untyped, import-not-found, unused-ignore]
    from robomimic.utils.dataset import SequenceDataset  # type: ignore[import-untyped, import-not-found, unused-ignore]

    task, store, _, path = exported
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
    assert environment.shape[1] == len(names) and tuple(names[-len(goal) :]) == goal

"""The HDF5 export read by the real robomimic 0.3 with its default settings: its
``SequenceDataset`` (``load_next_obs=True``, SWMR) and a few steps of its own training
loop (``robomimic.scripts.train.train``) with a BC config, then the checkpoint loaded back
as a policy. They need the learn extra (see tests/learn_extra.py)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import h5py  # type: ignore[import-untyped, unused-ignore]
import numpy as np
import pytest

from tests.export.conftest import SIZE
from tests.export.stores import Stores
from tests.learn_extra import require_learn_extra
from workcell.export.hdf5_export import HDF5_NAME, export_hdf5, image_name, next_rows
from workcell.export.options import ExportOptions

LOW_DIM = ("state", "environment_state")
DATASET_KEYS = ("actions", "rewards", "dones")
CAMERA = "wrist_l_cam"
TRAIN_STEPS = 3


@pytest.fixture(scope="module")
def image_hdf5(recorded: Stores, tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The short store exported to HDF5 with one camera."""
    out = tmp_path_factory.mktemp("hdf5_images") / "dataset"
    export_hdf5(recorded.short, out, ExportOptions(cameras=(CAMERA,), size=SIZE))
    return out / HDF5_NAME


def _sequence_dataset(path: Path, obs_keys: tuple[str, ...], **options: Any) -> Any:
    """robomimic's SequenceDataset with its defaults (next_obs loaded, SWMR on)."""
    from robomimic.utils import obs_utils  # type: ignore[import-untyped, import-not-found, unused-ignore]
    from robomimic.utils.dataset import SequenceDataset  # type: ignore[import-untyped, import-not-found, unused-ignore]

    images = [key for key in obs_keys if key.endswith("_image")]
    obs_utils.initialize_obs_modality_mapping_from_dict(
        {"low_dim": [key for key in obs_keys if key not in images], "rgb": images}
    )
    return SequenceDataset(str(path), obs_keys, DATASET_KEYS, **options)


def test_next_obs_is_the_following_row(hdf5_path: Path) -> None:
    with h5py.File(hdf5_path, "r") as file:
        for name in file["data"]:
            demo = file["data"][name]
            assert set(demo["next_obs"]) == set(demo["obs"]) == set(LOW_DIM)
            for key in LOW_DIM:
                current, following = demo["obs"][key][:], demo["next_obs"][key][:]
                assert np.array_equal(following[:-1], current[1:])
                assert np.array_equal(following[-1], current[-1])
        conventions = json.loads(file["data"].attrs["conventions"])
    assert "last row repeats" in conventions["next_obs"]


def test_next_rows_of_one_row_repeat_it() -> None:
    assert next_rows(np.array([[1.0, 2.0]])).tolist() == [[1.0, 2.0]]
    assert next_rows(np.zeros((0, 3))).shape == (0, 3)


def test_sequence_dataset_loads_every_demo_with_next_obs(hdf5_path: Path) -> None:
    require_learn_extra()
    dataset = _sequence_dataset(hdf5_path, LOW_DIM)
    with h5py.File(hdf5_path, "r") as file:
        total = int(file["data"].attrs["total"])
        first = file["data/demo_0"]
        state, next_state = first["obs/state"][:], first["next_obs/state"][:]
    assert len(dataset) == total
    item = dataset[3]  # demo_0 comes first
    assert item["obs"]["state"].shape == (1, 39)
    # boxes, the goal, then both relative to the robot (9 per box, the goal's point)
    assert item["next_obs"]["environment_state"].shape == (1, 32 + 2 + 36 + 2)
    assert item["actions"].shape == (1, 23)
    np.testing.assert_array_equal(item["obs"]["state"][0], state[3])
    np.testing.assert_array_equal(item["next_obs"]["state"][0], next_state[3])


def test_sequence_dataset_reads_images_and_their_next_obs(image_hdf5: Path) -> None:
    require_learn_extra()
    key = image_name(CAMERA)
    dataset = _sequence_dataset(image_hdf5, (*LOW_DIM, key), hdf5_cache_mode="low_dim")
    item = dataset[0]
    assert item["obs"][key].shape == (1, SIZE.height, SIZE.width, 3)
    with h5py.File(image_hdf5, "r") as file:
        images = file[f"data/demo_0/obs/{key}"][:]
        following = file[f"data/demo_0/next_obs/{key}"][:]
    np.testing.assert_array_equal(item["next_obs"][key][0], images[1])
    assert np.array_equal(following[:-1], images[1:]) and np.array_equal(following[-1], images[-1])


@pytest.mark.parametrize("algo", ["bc", "iql"])
def test_robomimic_trains_and_loads_the_checkpoint(
    algo: str, hdf5_path: Path, tmp_path: Path
) -> None:
    """robomimic's own training loop with the algorithm's default data settings (BC skips
    next_obs, offline RL such as IQL loads it; cached, SWMR) on the included demos;
    rollouts off (they need robomimic's env API)."""
    require_learn_extra()
    from robomimic.config import config_factory  # type: ignore[import-untyped, import-not-found, unused-ignore]
    from robomimic.scripts.train import train  # type: ignore[import-untyped, import-not-found, unused-ignore]
    from robomimic.utils import file_utils, torch_utils  # type: ignore[import-untyped, import-not-found, unused-ignore]

    config = config_factory(algo)
    with config.values_unlocked():
        config.train.data = str(hdf5_path)
        config.train.output_dir = str(tmp_path / "runs")
        config.train.hdf5_filter_key = "included"
        config.train.num_epochs = 1
        config.train.batch_size = 16
        config.experiment.name = "workcell"
        config.experiment.epoch_every_n_steps = TRAIN_STEPS
        config.experiment.rollout.enabled = False
        config.experiment.logging.terminal_output_to_txt = False
        config.experiment.save.epochs = [1]
        config.observation.modalities.obs.low_dim = list(LOW_DIM)
        config.observation.modalities.obs.rgb = []
    assert config.train.hdf5_load_next_obs == (algo != "bc") and config.train.hdf5_use_swmr
    config.lock()
    train(config, device=torch_utils.get_torch_device(try_to_use_cuda=False))

    (checkpoint,) = (tmp_path / "runs" / "workcell").glob("*/models/model_epoch_1.pth")
    policy, _ = file_utils.policy_from_checkpoint(ckpt_path=str(checkpoint), device="cpu")
    policy.start_episode()
    with h5py.File(hdf5_path, "r") as file:
        obs = {key: file[f"data/demo_0/obs/{key}"][0] for key in LOW_DIM}
    action = policy(obs)
    assert action.shape == (23,) and np.isfinite(action).all()

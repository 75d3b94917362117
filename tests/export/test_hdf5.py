"""The robomimic-style HDF5 export, read back with h5py."""

from __future__ import annotations

import json
from pathlib import Path

import h5py  # type: ignore[import-untyped, unused-ignore]
import mujoco
import numpy as np

from tests.export.conftest import SIZE
from tests.export.stores import Stores
from workcell.envs import ENV_ID
from workcell.export.env_args import ENV_NAME
from workcell.export.features import ACTION_NAMES, STATE_NAMES, column_matrix
from workcell.export.hdf5_export import HDF5_NAME, PROVENANCE_NAME, export_hdf5
from workcell.export.options import ExportOptions
from workcell.record.store import Store


def test_layout_is_robomimics(hdf5_path: Path, recorded: Stores) -> None:
    with Store.open(recorded.mixed, writer=False) as store:
        trials = store.trials()
    with h5py.File(hdf5_path, "r") as file:
        data = file["data"]
        env_args = json.loads(data.attrs["env_args"])
        assert env_args["env_name"] == ENV_NAME == ENV_ID
        assert env_args["type"] == 2
        assert env_args["env_kwargs"]["session_parameters"]["recording"]["sampling_rate_hz"] == 20
        demos = sorted(data, key=lambda name: int(name.split("_")[1]))
        assert demos == [f"demo_{i}" for i in range(len(trials))]
        assert data.attrs["total"] == sum(t.n_frames or 0 for t in trials)
        assert json.loads(data.attrs["action_names"]) == list(ACTION_NAMES)
        assert json.loads(data.attrs["state_names"]) == list(STATE_NAMES)
        for name in demos:
            demo = data[name]
            n = demo.attrs["num_samples"]
            assert demo["actions"].shape == (n, 23)
            assert demo["rewards"].shape == demo["dones"].shape == (n,)
            assert demo["dones"][-1] == 1 and demo["dones"][:-1].sum() == 0
            assert demo["obs/state"].shape == (n, 39)
            # boxes, the goal, then both relative to the robot (9 per box, the goal's point)
            assert demo["obs/environment_state"].shape == (n, 32 + 2 + 36 + 2)
            model = mujoco.MjModel.from_xml_string(demo.attrs["model_file"])
            assert demo["states"].shape == (n, model.nq + model.nv)


def test_demos_carry_provenance_and_masks_filter_them(hdf5_path: Path, recorded: Stores) -> None:
    with Store.open(recorded.mixed, writer=False) as store:
        trials = {t.trial_id: t for t in store.trials()}
    with h5py.File(hdf5_path, "r") as file:
        names = {name: file[f"data/{name}"].attrs for name in file["data"]}
        masks = {key: {n.decode() for n in file[f"mask/{key}"][:]} for key in file["mask"]}
        for name, attrs in names.items():
            trial = trials[attrs["trial_id"]]
            assert attrs["session_id"] == trial.session_id
            assert attrs["outcome"] == trial.outcome
            assert attrs["num_samples"] == trial.n_frames
            assert json.loads(attrs["quality_flags"]) == list(trial.quality_flags)
            assert name in masks[trial.outcome or ""]
            assert (name in masks["included"]) == bool(attrs["included"])
            assert (name in masks["excluded"]) != bool(attrs["included"])
        document = json.loads(file[PROVENANCE_NAME][()])
        demo_trials = [names[f"demo_{i}"]["trial_id"] for i in range(len(names))]
    assert [e["trial_id"] for e in document["episodes"]] == demo_trials
    assert document["selection"]["include_all"] is True
    assert len(masks["success"]) == 2
    assert len(masks["timeout"]) == len(masks["interrupted"]) == 1
    assert len(masks["included"]) == 2 and len(masks["excluded"]) == 2


def test_states_restore_the_recorded_base_and_joints(hdf5_path: Path, recorded: Stores) -> None:
    with h5py.File(hdf5_path, "r") as file:
        demo = file["data/demo_0"]
        states = demo["states"][:]
        state_obs = demo["obs/state"][:]
        model = mujoco.MjModel.from_xml_string(demo.attrs["model_file"])
        trial_id = demo.attrs["trial_id"]
    with Store.open(recorded.mixed, writer=False) as store:
        frames = store.frames(trial_id)
    base = [model.jnt_qposadr[model.joint(n).id] for n in ("base_x", "base_y", "base_yaw")]
    recorded_base = column_matrix(frames, ("base_x", "base_y", "base_yaw"))
    assert np.array_equal(states[:, base], recorded_base)
    assert np.array_equal(state_obs, column_matrix(frames, STATE_NAMES))


def test_cameras_become_image_observations(recorded: Stores, tmp_path: Path) -> None:
    options = ExportOptions(cameras=("wrist_r_cam",), size=SIZE)
    export_hdf5(recorded.short, tmp_path / "out", options)
    with h5py.File(tmp_path / "out" / HDF5_NAME, "r") as file:
        demo = file["data/demo_0"]
        images = demo["obs/wrist_r_cam_image"]
        assert images.shape == (demo.attrs["num_samples"], SIZE.height, SIZE.width, 3)
        assert images.dtype == np.uint8
        assert images[0].std() > 1.0  # not a blank picture

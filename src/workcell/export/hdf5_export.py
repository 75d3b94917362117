"""``export_hdf5``: a store's trials as a robomimic-style HDF5 file (``workcell.hdf5``).

::

    data                 attrs: env_args (JSON: env_name, type, env_kwargs: the session
                         parameters every demo shares), env_args_differ (JSON: the
                         settings that differ between demos), total, fps, names of the
                         state / environment_state / action dimensions, conventions (JSON)
    data/demo_<i>        attrs: num_samples, model_file (the world's MJCF XML), env_args
                         (JSON: its own session's parameters whole), and the episode's
                         provenance (trial id, session id, operator_id, condition,
                         study_step, outcome, flags, ...)
        states           (n, nq + nv) restored MuJoCo qpos and qvel (see .restore)
        actions          (n, 23)   rewards (n,)   dones (n,)
        intervention     (n,) 1 on the rows a person who took over from the trial's driver
                         drove (a correction), else 0: the per-frame correction mask
        obs/state        (n, 39)   obs/environment_state (n, boxes, goal, relative)
        obs/<camera>_image  (n, height, width, 3) uint8, when cameras are asked for: the
                         trial's recorded video decoded, or rendered from its states
                         (attribute camera_sources says which, and why)
        next_obs/<key>   for every obs/<key>: the observation of the next row (images
                         too, as robomimic stores them: twice the image data)
    mask/<filter>        demo names: success, timeout, interrupted, failed, included, excluded
    workcell_provenance  the export-level provenance document (JSON text; a dataset, as
                         it outgrows HDF5's 64 KiB attribute limit with many demos)

Rows, actions, rewards and dones follow :mod:`workcell.export.episode_data` (``dones`` is
1 on the last row of every demo). ``next_obs`` row ``t`` is ``obs`` row ``t + 1``; the last
row repeats its own observation, as robomimic's own conversion of recorded data does
(``scripts/conversion/convert_d4rl.py``; there is no frame after the last one, and its
``dones`` is 1). robomimic's loaders read ``next_obs`` by default (``SequenceDataset``'s
``load_next_obs``; the offline RL configs' ``train.hdf5_load_next_obs``). ``env_args`` makes
``gymnasium.make`` build the matching environment (:mod:`workcell.export.env_args`): a
demo's own holds its session's stored parameters; the file's, those all sessions share.
"""

from __future__ import annotations

import json
import os
import time
from collections.abc import Mapping
from typing import Any, TypeVar

import h5py  # type: ignore[import-untyped, unused-ignore]
import numpy as np
from numpy.typing import NDArray

from workcell.export.boxes import environment_names
from workcell.export.camera_images import CameraPlan, describe, episode_images
from workcell.export.camera_sources import CameraSource
from workcell.export.env_args import env_args, shared_parameters
from workcell.export.episode_data import CONVENTIONS
from workcell.export.features import ACTION_NAMES, STATE_NAMES
from workcell.export.loading import ExportSummary, LoadedEpisode, Progress, load_episodes
from workcell.export.manifest import provenance_document
from workcell.export.options import ExportOptions
from workcell.export.provenance import Provenance
from workcell.export.replay_world import WorldPool
from workcell.export.source import ExportSource, check_output, open_source
from workcell.record.store import Store
from workcell.sim.scene import world_spec

T = TypeVar("T", bound=np.generic)

HDF5_NAME = "workcell.hdf5"
PROVENANCE_NAME = "workcell_provenance"
FILTERS: tuple[str, ...] = (
    "success",
    "timeout",
    "interrupted",
    "failed",
    "included",
    "excluded",
)
"""robomimic filter masks: one per outcome (``failed`` since the task API), then the
included and the excluded trials."""
NEXT_OBS_CONVENTION = (
    "next_obs row t is obs row t+1; the last row repeats its own observation (robomimic's "
    "convention for recorded data)"
)


def export_hdf5(
    store_path: str | os.PathLike[str],
    out_dir: str | os.PathLike[str],
    options: ExportOptions | None = None,
    progress: Progress | None = None,
) -> ExportSummary:
    """Export the store's selected trials into ``out_dir/workcell.hdf5`` (``out_dir`` new
    or empty)."""
    started = time.perf_counter()
    options = options or ExportOptions()
    out = check_output(out_dir)
    source = open_source(store_path, options.trials)
    out.mkdir(parents=True, exist_ok=True)
    records: list[Provenance] = []
    frames = 0
    models: dict[str, str] = {}
    with Store.open(source.path, writer=False) as store:
        cameras = CameraPlan(store, source, options, copies_videos=False)
        options = cameras.options
        with (
            WorldPool(options.image_size) as worlds,
            h5py.File(out / HDF5_NAME, "w") as file,
        ):
            data = file.create_group("data")
            for episode in load_episodes(store, source, worlds, progress):
                session_id = episode.source.session.session_id
                if session_id not in models:
                    models[session_id] = world_spec(source.configs[session_id].world).to_xml()
                sources = cameras.sources(episode)
                if sources and progress is not None:
                    progress(describe(episode, sources, len(source.episodes)))
                _write_demo(data, episode, models[session_id], options, sources)
                records.append(episode.provenance)
                frames += episode.arrays.length
            _write_header(data, source, frames)
            _write_masks(file, records)
            document = provenance_document(source, options, records, cameras.decided)
            file.create_dataset(PROVENANCE_NAME, data=json.dumps(document))
    return ExportSummary(
        out,
        len(records),
        frames,
        len(options.cameras),
        time.perf_counter() - started,
        recorded_videos=cameras.recorded,
        rendered_videos=cameras.rendered,
        selection=source.selection,
    )


def demo_name(index: int) -> str:
    return f"demo_{index}"


def _write_demo(
    data: Any,
    episode: LoadedEpisode,
    model_xml: str,
    options: ExportOptions,
    sources: Mapping[str, CameraSource],
) -> None:
    assert episode.world is not None
    arrays = episode.arrays
    demo = data.create_group(demo_name(episode.index))
    demo.attrs["num_samples"] = arrays.length
    demo.attrs["model_file"] = model_xml
    for name, value in episode.provenance.as_attributes().items():
        demo.attrs[name] = value
    demo.attrs["env_args"] = json.dumps(env_args(episode.source.session.parameters))
    demo.create_dataset("states", data=episode.world.mujoco_states(episode.states))
    demo.create_dataset("actions", data=arrays.action)
    demo.create_dataset("rewards", data=arrays.reward)
    demo.create_dataset("dones", data=arrays.done.astype(np.int64))
    demo.create_dataset("intervention", data=arrays.intervention.astype(np.int64))
    obs, next_obs = demo.create_group("obs"), demo.create_group("next_obs")
    for key, values in (("state", arrays.state), ("environment_state", arrays.environment)):
        obs.create_dataset(key, data=values)
        next_obs.create_dataset(key, data=next_rows(values))
    if sources:
        demo.attrs["camera_sources"] = json.dumps([s.as_dict() for s in sources.values()])
        n, size = arrays.length, options.image_size
        shape = (n, size.height, size.width, 3)
        chunks = (1, size.height, size.width, 3)
        images = {
            camera: tuple(
                group.create_dataset(image_name(camera), shape, np.uint8, chunks=chunks)
                for group in (obs, next_obs)
            )
            for camera in options.cameras
        }
        for i, frame in enumerate(episode_images(episode, sources)):
            for camera, image in frame.items():
                current, following = images[camera]
                current[i] = image
                if i > 0:
                    following[i - 1] = image
                if i == n - 1:
                    following[i] = image


def image_name(camera: str) -> str:
    """The observation key of a camera's images: ``<camera>_image``."""
    return f"{camera}_image"


def next_rows(values: NDArray[T]) -> NDArray[T]:
    """``values`` shifted one row up, the last row repeated (see ``next_obs`` above)."""
    return np.concatenate([values[1:], values[-1:]]) if len(values) else values.copy()


def _write_header(data: Any, source: ExportSource, frames: int) -> None:
    shared, differ = shared_parameters([s.parameters for s in source.sessions])
    data.attrs["env_args"] = json.dumps(env_args(shared))
    data.attrs["env_args_differ"] = json.dumps(differ)
    data.attrs["total"] = frames
    data.attrs["state_names"] = json.dumps(list(STATE_NAMES))
    data.attrs["action_names"] = json.dumps(list(ACTION_NAMES))
    data.attrs["environment_state_names"] = json.dumps(
        list(environment_names(source.pool_size, source.goal_names))
    )
    data.attrs["conventions"] = json.dumps({**CONVENTIONS, "next_obs": NEXT_OBS_CONVENTION})
    data.attrs["fps"] = source.fps


def _write_masks(file: Any, records: list[Provenance]) -> None:
    members: dict[str, list[str]] = {name: [] for name in FILTERS}
    for record in records:
        name = demo_name(record.episode_index)
        members[record.outcome].append(name)
        members["included" if record.included else "excluded"].append(name)
    mask = file.create_group("mask")
    for name, demos in members.items():
        mask.create_dataset(name, data=np.array(demos, dtype="S"))
